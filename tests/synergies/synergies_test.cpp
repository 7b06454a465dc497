#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/QR>
#include <cmath>
#include <filesystem>
#include <random>

#include "common/model.h"
#include "stages/segment/segmentation.h"
#include "stages/synergies/segment_pca.h"
#include "stages/synergies/synergies.h"
#include "tests/support/demo_motion.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

TEST(SegmentPca, RecoversThreeKnownDirectionsAndTheirVariance) {
  const int samples = 400, width = 35;
  std::mt19937 random(3);
  std::normal_distribution<double> normal;
  // Three orthonormal directions, by QR of a random matrix.
  Eigen::MatrixXd basis = Eigen::MatrixXd::NullaryExpr(width, 3, [&] { return normal(random); });
  basis = Eigen::HouseholderQR<Eigen::MatrixXd>(basis).householderQ() * Eigen::MatrixXd::Identity(width, 3);
  // Zero-mean, mutually orthogonal profiles over the grid: sines of 1, 2 and 3 periods.
  const double amplitude[3] = {3.0, 1.5, 0.5};
  Eigen::MatrixXd velocities(samples, width);
  Eigen::VectorXd offset = Eigen::VectorXd::NullaryExpr(width, [&] { return normal(random); });
  for (int t = 0; t < samples; ++t) {
    Eigen::VectorXd row = offset;
    for (int i = 0; i < 3; ++i) row += amplitude[i] * std::sin(2 * M_PI * (i + 1) * t / samples) * basis.col(i);
    velocities.row(t) = row.transpose();
  }
  const SegmentSynergies pca = ComputeSegmentSynergies(velocities, 3);
  const double total = amplitude[0] * amplitude[0] + amplitude[1] * amplitude[1] + amplitude[2] * amplitude[2];
  for (int i = 0; i < 3; ++i) {
    EXPECT_GT(std::abs(pca.components.row(i).dot(basis.col(i).transpose())), 0.999) << i;
    EXPECT_NEAR(pca.explained_variance_ratio[i], amplitude[i] * amplitude[i] / total, 1e-6) << i;
  }
  EXPECT_LT((pca.mean - offset).norm(), 1e-12);
  EXPECT_LT((pca.components * pca.components.transpose() - Eigen::Matrix3d::Identity()).norm(), 1e-12);
  EXPECT_EQ(pca.components_for_90_percent, 2);  // 9 + 2.25 of 11.5 = 97.8 %
  // With a_i = σ_i the rank-3 reconstruction is exact here (the data has rank 3 about its mean).
  EXPECT_LT((ReconstructVelocities(pca, pca.singular_values) - velocities).cwiseAbs().maxCoeff(), 1e-10);
}

class RealSegments : public ::testing::Test {
 protected:
  // One demo trial through ingest, retarget and segmentation, as the pipeline runs it.
  static void SetUpTestSuite() {
    motion_ = new MotionData(testing::DemoMotionOnG1("05_02"));
    const Model model = Model::Load(testing::SourcePath(testing::kG1Urdf));
    boundaries_ = new std::vector<int64_t>(SegmentMotion(*motion_, model, {}).boundaries);
  }
  static void TearDownTestSuite() {
    delete motion_;
    delete boundaries_;
  }
  static MotionData* motion_;
  static std::vector<int64_t>* boundaries_;
};
MotionData* RealSegments::motion_ = nullptr;
std::vector<int64_t>* RealSegments::boundaries_ = nullptr;

TEST_F(RealSegments, ReconstructionErrorFallsWithKAndIsExactAtFullRank) {
  ASSERT_GE(boundaries_->size(), 3u);
  SynergyOptions options;
  options.components = 1000;  // full rank
  const TrialSynergies trial = ComputeTrialSynergies(*motion_, *boundaries_, options);
  ASSERT_FALSE(trial.segments.empty());
  for (const auto& segment : trial.segments) {
    const SegmentSynergies& pca = segment.synergies;
    double previous = std::numeric_limits<double>::infinity();
    for (int k = 1; k <= pca.components.rows(); ++k) {
      const double error = (ReconstructVelocities(pca, pca.singular_values.head(k)) - segment.velocities).squaredNorm();
      EXPECT_LE(error, previous * (1 + 1e-12) + 1e-18) << "k=" << k;
      previous = error;
    }
    EXPECT_LT((ReconstructVelocities(pca, pca.singular_values) - segment.velocities).cwiseAbs().maxCoeff(),
              1e-9 * (1 + segment.velocities.cwiseAbs().maxCoeff()));
  }
}

TEST_F(RealSegments, FileRoundTripAndHeadingInvariance) {
  SynergyOptions options;
  options.labels.style = "modern";
  const TrialSynergies trial = ComputeTrialSynergies(*motion_, *boundaries_, options);
  const std::string path = std::filesystem::temp_directory_path() / ("syn_roundtrip_" + std::to_string(::getpid()) + ".h5");
  {
    IntermediateWriter writer(path, {kSynergiesSchema, kSynergiesSchemaVersion, "test", options.ToJson(), nlohmann::json::array()});
    WriteTrialSynergies(writer, trial, options.labels);
    writer.commit();
  }
  SynergyLabels labels;
  const TrialSynergies back = ReadTrialSynergies(path, &labels);
  EXPECT_EQ(labels.style, "modern");
  ASSERT_EQ(back.segments.size(), trial.segments.size());
  EXPECT_LT((back.segments[0].synergies.components - trial.segments[0].synergies.components).cwiseAbs().maxCoeff(), 1e-15);
  std::filesystem::remove(path);
  // Turning the whole motion about the vertical leaves the base velocities in the heading frame unchanged.
  MotionData turned = *motion_;
  const Eigen::Quaterniond turn(Eigen::AngleAxisd(1.2, Eigen::Vector3d::UnitZ()));
  for (int64_t t = 0; t < turned.frames(); ++t) {
    double* q = &turned.q[static_cast<size_t>(t * turned.nq())];
    const Eigen::Quaterniond base = turn * Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
    q[0] = base.w(), q[1] = base.x(), q[2] = base.y(), q[3] = base.z();
    double* u = &turned.u[static_cast<size_t>(t * turned.nu())];
    const Eigen::Vector3d w = turn * Eigen::Vector3d(u[0], u[1], u[2]), v = turn * Eigen::Vector3d(u[3], u[4], u[5]);
    for (int i = 0; i < 3; ++i) u[i] = w[i], u[3 + i] = v[i];
  }
  const TrialSynergies turned_trial = ComputeTrialSynergies(turned, *boundaries_, options);
  EXPECT_LT((turned_trial.segments[0].velocities - trial.segments[0].velocities).cwiseAbs().maxCoeff(), 1e-9);
}

}  // namespace
}  // namespace syn
