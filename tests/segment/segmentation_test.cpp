#include "stages/segment/segmentation.h"

#include <gtest/gtest.h>

#include <cmath>

#include <Eigen/Geometry>

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

// ΔP between analysis instants, computed here step by step: the configuration blended component-wise between
// the neighbouring frames (the base quaternion toward the nearer sign, left off the unit sphere) and
// normalised once, by Workspace::setQ. The segmentation must give these numbers to the last bit: the demo
// release's SHA-256 depends on them, and normalising a second time (Interpolate, then setQ) moves ΔP by
// about 1e-14.
TEST(Segmentation, DeltaPIsTheOnceNormalisedBlendBitForBit) {
  const Model model = Model::Load(testing::SourcePath("datasets/robots/unitree_g1/g1_29dof.urdf"));
  const int64_t nq = model.nq(), nu = model.nu();
  MotionData motion;
  motion.coordinate_names = model.coordinateNames();
  motion.velocity_names = model.velocityNames();
  motion.model_sha256 = model.sourceSha256();
  const int frames = 60;  // 2 s at 30 Hz, analysed at 100 Hz: most instants fall between frames
  for (int t = 0; t < frames; ++t) {
    const double time = t / 30.0;
    motion.time_s.push_back(time);
    Eigen::VectorXd q = model.defaultQ();
    // The base turning about a tilted axis, 0.15 rad per frame; from frame 30 on stored with the opposite
    // sign (the same rotation), so the nearer-sign branch is taken once.
    const Eigen::Quaterniond base(Eigen::AngleAxisd(4.5 * time, Eigen::Vector3d(0.3, -0.5, 0.8).normalized()));
    const double sign = t < 30 ? 1.0 : -1.0;
    q.head<4>() << sign * base.w(), sign * base.x(), sign * base.y(), sign * base.z();
    for (int64_t i = 7; i < nq; ++i) q[i] = 0.4 * std::sin(2.0 * time + 0.3 * static_cast<double>(i));
    motion.q.insert(motion.q.end(), q.data(), q.data() + nq);
    for (int64_t i = 0; i < nu; ++i) motion.u.push_back(std::cos(1.5 * time + 0.2 * static_cast<double>(i)));
  }
  motion.udot.assign(motion.u.size(), 0.0);
  motion.tau.assign(motion.u.size(), 0.0);

  SegmentOptions options;  // generalized momentum, 100 Hz
  const Segmentation segmentation = SegmentMotion(motion, model, options);
  ASSERT_EQ(segmentation.delta_p.size(), 197u);  // 0 to 59/30 s at 100 Hz

  Workspace workspace(model);
  Eigen::VectorXd q(nq), u(nu), p(nu), p_before(nu);
  size_t frame = 0;
  for (size_t i = 0; i < segmentation.delta_p.size(); ++i) {
    const double time = static_cast<double>(i) / options.analysis_rate;
    while (frame + 2 < static_cast<size_t>(frames) && motion.time_s[frame + 1] <= time) ++frame;
    const double s = (time - motion.time_s[frame]) / (motion.time_s[frame + 1] - motion.time_s[frame]);
    const double* q0 = &motion.q[frame * static_cast<size_t>(nq)];
    const double* q1 = &motion.q[(frame + 1) * static_cast<size_t>(nq)];
    const double dot = q0[0] * q1[0] + q0[1] * q1[1] + q0[2] * q1[2] + q0[3] * q1[3];
    for (int64_t k = 0; k < nq; ++k) {
      const double toward = k < 4 && dot < 0 ? -q1[k] : q1[k];
      q[k] = (1 - s) * q0[k] + s * toward;
    }
    for (int64_t k = 0; k < nu; ++k) {
      const double u0 = motion.u[frame * static_cast<size_t>(nu) + static_cast<size_t>(k)];
      const double u1 = motion.u[(frame + 1) * static_cast<size_t>(nu) + static_cast<size_t>(k)];
      u[k] = (1 - s) * u0 + s * u1;
    }
    workspace.setQ(q);
    workspace.calcMassTimes(u, p);
    if (i > 0) {
      EXPECT_EQ(segmentation.delta_p[i], (p - p_before).norm()) << "analysis instant " << i;
    }
    p_before.swap(p);
  }
}

TEST(Segmentation, RefusesAnotherRobotsMotion) {
  const Model model = Model::Load(testing::SourcePath("datasets/robots/unitree_g1/g1_29dof.urdf"));
  MotionData motion = SteppedMotion(model, {});
  motion.model_sha256 = "0123456789abcdef";
  EXPECT_THROW((void)SegmentMotion(motion, model, {}), DataError);
}

}  // namespace
}  // namespace syn
