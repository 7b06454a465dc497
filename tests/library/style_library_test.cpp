#include "stages/library/style_library.h"
#include "stages/synergies/segment_pca.h"

#include <gtest/gtest.h>

#include <Eigen/QR>
#include <cmath>
#include <random>

#include "common/error.h"

namespace syn {
namespace {

// A trial with `segments` segments whose velocities live in span(basis) (plus a per-segment offset).
LabelledTrial SyntheticTrial(const std::string& id, const std::string& style, const std::string& motion_class,
                             const Eigen::MatrixXd& basis, int segments, unsigned seed) {
  std::mt19937 random(seed);
  std::normal_distribution<double> normal;
  LabelledTrial trial;
  trial.labels.trial = id;
  trial.labels.style = style;
  trial.labels.motion_class = motion_class;
  for (int i = 0; i < basis.rows(); ++i) trial.synergies.velocity_names.push_back(std::to_string(i));
  for (int s = 0; s < segments; ++s) {
    TrialSynergies::Segment segment;
    const Eigen::MatrixXd coefficients = Eigen::MatrixXd::NullaryExpr(50, basis.cols(), [&] { return normal(random); });
    const Eigen::RowVectorXd offset = Eigen::RowVectorXd::NullaryExpr(basis.rows(), [&] { return normal(random); });
    segment.velocities = (coefficients * basis.transpose()).rowwise() + offset;
    segment.synergies = ComputeSegmentSynergies(segment.velocities, 3);
    trial.synergies.segments.push_back(segment);
  }
  return trial;
}

TEST(StyleLibrary, SharedSubspaceIsFoundAndRetainsAllVariance) {
  std::mt19937 random(9);
  std::normal_distribution<double> normal;
  Eigen::MatrixXd basis = Eigen::MatrixXd::NullaryExpr(20, 3, [&] { return normal(random); });
  basis = Eigen::HouseholderQR<Eigen::MatrixXd>(basis).householderQ() * Eigen::MatrixXd::Identity(20, 3);
  Eigen::MatrixXd other = Eigen::MatrixXd::NullaryExpr(20, 3, [&] { return normal(random); });
  other = Eigen::HouseholderQR<Eigen::MatrixXd>(other).householderQ() * Eigen::MatrixXd::Identity(20, 3);
  const std::vector<LabelledTrial> trials = {SyntheticTrial("t1", "salsa", "dance", basis, 4, 1),
                                             SyntheticTrial("t2", "salsa", "dance", basis, 3, 2),
                                             SyntheticTrial("t3", "walk", "walk", other, 2, 3)};
  const SynergyLibrary library = BuildLibrary(trials, {"a.h5", "b.h5", "c.h5"}, 3);
  ASSERT_EQ(library.styles.size(), 2u);
  const StyleBasis& salsa = library.styles.at("salsa");
  EXPECT_EQ(salsa.segments, 7);
  // The style basis spans the generating subspace: projecting the true basis onto it loses nothing.
  const Eigen::MatrixXd projected = salsa.components.transpose() * (salsa.components * basis);
  EXPECT_LT((projected - basis).norm(), 1e-9);
  for (double retained : salsa.retained_variance) EXPECT_NEAR(retained, 1.0, 1e-12);
  EXPECT_NEAR(salsa.explained_variance_ratio.sum(), 1.0, 1e-12);
  // Per class: the mean and spread of per-segment PC ratios, recomputed here.
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  int count = 0;
  for (int t = 0; t < 2; ++t) {
    for (const auto& segment : trials[t].synergies.segments) mean += segment.synergies.explained_variance_ratio.head<3>(), ++count;
  }
  mean /= count;
  EXPECT_LT((library.classes.at("dance").mean_ratio - mean).norm(), 1e-12);
  EXPECT_EQ(library.classes.at("dance").segments, 7);
}

TEST(StyleLibrary, RefusesTrialsWithDifferentVelocities) {
  Eigen::MatrixXd basis = Eigen::MatrixXd::Identity(5, 3);
  LabelledTrial a = SyntheticTrial("a", "s", "c", basis, 1, 1);
  LabelledTrial b = SyntheticTrial("b", "s", "c", Eigen::MatrixXd::Identity(6, 3), 1, 2);
  EXPECT_THROW((void)BuildLibrary({a, b}, {"a.h5", "b.h5"}, 3), DataError);
}

}  // namespace
}  // namespace syn
