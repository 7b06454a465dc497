// The principal axes syn-synergies and syn-library share (common/principal_axes.h), against samples built
// from known axes: orthogonal score columns (whole periods of cosines and sines) times a known rotation,
// so the SVD's answer is known in closed form up to the signs the convention fixes.
#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include <Eigen/Geometry>

#include "common/principal_axes.h"

namespace syn {
namespace {

struct KnownSamples {
  Eigen::MatrixXd centred;  // N × 3
  Eigen::Matrix3d axes;     // the true axes, largest variance first
  Eigen::Vector3d singular_values;
  Eigen::MatrixXd scores;   // N × 3, unit columns
};

KnownSamples MakeSamples() {
  constexpr int samples = 64;
  KnownSamples known;
  Eigen::MatrixXd s(samples, 3);
  for (int t = 0; t < samples; ++t) {
    const double phase = 2 * std::numbers::pi * t / samples;
    s.row(t) << 3 * std::cos(phase), 2 * std::sin(phase), std::cos(2 * phase);
  }
  known.axes = (Eigen::AngleAxisd(0.7, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(-0.4, Eigen::Vector3d::UnitY()) *
                Eigen::AngleAxisd(1.1, Eigen::Vector3d::UnitX())).toRotationMatrix();
  known.centred = s * known.axes.transpose();
  known.singular_values = Eigen::Vector3d(3, 2, 1) * std::sqrt(samples / 2.0);
  known.scores = s * known.singular_values.cwiseInverse().asDiagonal();
  return known;
}

TEST(PrincipalAxes, KnownAxesComeBackWithTheirLargestEntryPositive) {
  const KnownSamples known = MakeSamples();
  const PrincipalAxes principal = ComputePrincipalAxes(known.centred, 3, /*with_scores=*/true);
  ASSERT_EQ(principal.axes.cols(), 3);
  ASSERT_EQ(principal.scores.cols(), 3);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(principal.singular_values[c], known.singular_values[c], 1e-9);
    // σ² over Σσ²: 9, 4 and 1 fourteenths.
    EXPECT_NEAR(principal.explained_variance_ratio[c], std::pow(3.0 - c, 2) / 14.0, 1e-12);
    // The true axis, turned so that its largest entry (by magnitude) is positive.
    Eigen::Index largest = 0;
    known.axes.col(c).cwiseAbs().maxCoeff(&largest);
    const double sign = known.axes(largest, c) < 0 ? -1.0 : 1.0;
    EXPECT_LT((principal.axes.col(c) - sign * known.axes.col(c)).norm(), 1e-9) << "axis " << c;
    // The scores turn with their axis, so the decomposition still gives the samples back.
    EXPECT_LT((principal.scores.col(c) - sign * known.scores.col(c)).norm(), 1e-9) << "scores " << c;
  }
  const Eigen::MatrixXd rebuilt =
      principal.scores * principal.singular_values.asDiagonal() * principal.axes.transpose();
  EXPECT_LT((rebuilt - known.centred).norm(), 1e-9 * known.centred.norm());
}

TEST(PrincipalAxes, FewerComponentsAndNoScoresGiveTheSameLeadingAxes) {
  const KnownSamples known = MakeSamples();
  const PrincipalAxes all = ComputePrincipalAxes(known.centred, 3, /*with_scores=*/true);
  const PrincipalAxes two = ComputePrincipalAxes(known.centred, 2, /*with_scores=*/false);
  ASSERT_EQ(two.axes.cols(), 2);
  EXPECT_EQ(two.scores.size(), 0);
  EXPECT_EQ(two.singular_values.size(), 3);  // every singular value, for the explained-variance ratios
  EXPECT_LT((two.axes - all.axes.leftCols(2)).norm(), 1e-12);
  ASSERT_EQ(two.explained_variance_ratio.size(), 2);  // of all the variance, not of the two kept
  EXPECT_NEAR(two.explained_variance_ratio.sum(), 13.0 / 14.0, 1e-12);
  // More components than the samples have: capped at min(rows, cols).
  EXPECT_EQ(ComputePrincipalAxes(known.centred, 10, false).axes.cols(), 3);
}

}  // namespace
}  // namespace syn
