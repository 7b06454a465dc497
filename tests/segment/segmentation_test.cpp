#include "stages/segment/segmentation.h"

#include <gtest/gtest.h>

#include <cmath>

#include "common/error.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

// G1 standing still, its base velocity stepping at known times: u(t) piecewise constant.
MotionData SteppedMotion(const Model& model, const std::vector<std::pair<double, double>>& steps) {
  MotionData motion;
  motion.coordinate_names = model.coordinateNames();
  motion.velocity_names = model.velocityNames();
  motion.model_sha256 = model.sourceSha256();
  const int frames = 400;  // 4 s at 100 Hz
  for (int t = 0; t < frames; ++t) {
    const double time = t / 100.0;
    motion.time_s.push_back(time);
    Eigen::VectorXd q = model.defaultQ();
    motion.q.insert(motion.q.end(), q.data(), q.data() + q.size());
    double velocity = 0;
    for (const auto& [at, value] : steps) {
      if (time >= at - 1e-9) velocity = value;
    }
    for (int i = 0; i < model.nu(); ++i) motion.u.push_back(i == 3 ? velocity : 0.0);  // base v_x
  }
  motion.udot.assign(motion.u.size(), 0.0);
  motion.tau.assign(motion.u.size(), 0.0);
  return motion;
}

TEST(Segmentation, SpikesAtKnownTimesGiveThoseBoundariesAndMinDurationSuppressesCloseOnes) {
  const Model model = Model::Load(testing::SourcePath("datasets/robots/unitree_g1/g1_29dof.urdf"));
  const MotionData motion = SteppedMotion(model, {{1.0, 0.5}, {2.0, -0.5}, {2.3, 0.5}});
  SegmentOptions options;
  options.momentum = MomentumKind::kCentroidal;
  const Segmentation segmentation = SegmentMotion(motion, model, options);
  EXPECT_EQ(segmentation.boundaries, (std::vector<int64_t>{0, 100, 200, 400}));  // 2.3 s is 0.3 s after 2.0 s
  // Independent: a pure base translation changes the linear momentum by (total mass) × Δv.
  EXPECT_NEAR(segmentation.delta_p[100], model.totalMass() * 0.5, 1e-9);
  EXPECT_NEAR(segmentation.delta_p[200], model.totalMass() * 1.0, 1e-9);
  EXPECT_NEAR(segmentation.delta_p[230], model.totalMass() * 1.0, 1e-9);
  EXPECT_NEAR(segmentation.delta_p[150], 0.0, 1e-9);
  options.min_duration = 0.2;
  EXPECT_EQ(SegmentMotion(motion, model, options).boundaries, (std::vector<int64_t>{0, 100, 200, 230, 400}));
  // Generalized momentum: same boundaries (A u of a base translation is large too).
  options.momentum = MomentumKind::kGeneralized;
  EXPECT_EQ(SegmentMotion(motion, model, options).boundaries, (std::vector<int64_t>{0, 100, 200, 230, 400}));
  // A threshold above every jump gives one segment.
  options.threshold = model.totalMass() * 2;
  EXPECT_EQ(SegmentMotion(motion, model, options).boundaries, (std::vector<int64_t>{0, 400}));
}

TEST(Segmentation, QuantileThresholdAndAnalysisRate) {
  const Model model = Model::Load(testing::SourcePath("datasets/robots/unitree_g1/g1_29dof.urdf"));
  const MotionData motion = SteppedMotion(model, {{1.0, 0.5}, {2.0, -0.5}});
  SegmentOptions options;
  options.threshold_quantile = 0.5;  // median dP is 0: every jump exceeds it
  options.analysis_rate = 50;
  const Segmentation segmentation = SegmentMotion(motion, model, options);
  EXPECT_EQ(segmentation.analysis_time.size(), 200u);  // 3.99 s at 50 Hz
  EXPECT_EQ(segmentation.threshold_used, 0.0);
  EXPECT_EQ(segmentation.boundaries, (std::vector<int64_t>{0, 100, 200, 400}));
}

TEST(Segmentation, RefusesAnotherRobotsMotion) {
  const Model model = Model::Load(testing::SourcePath("datasets/robots/unitree_g1/g1_29dof.urdf"));
  MotionData motion = SteppedMotion(model, {});
  motion.model_sha256 = "0123456789abcdef";
  EXPECT_THROW((void)SegmentMotion(motion, model, {}), DataError);
}

}  // namespace
}  // namespace syn
