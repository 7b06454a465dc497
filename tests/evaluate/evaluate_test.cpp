#include <gtest/gtest.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>

#include "common/model.h"
#include "stages/evaluate/evaluate.h"
#include "common/foot_sliding.h"
#include "stages/evaluate/motion_metrics.h"
#include "stages/evaluate/synergy_monte_carlo.h"
#include "stages/segment/segmentation.h"
#include "stages/synergies/synergies.h"
#include "tests/support/demo_motion.h"
#include "tests/support/scratch_file.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

Model LoadUrdfText(const std::string& name, const std::string& text, FloatingBase base) {
  const testing::ScratchFile urdf(name, ".urdf", text);
  return Model::Load(urdf.path(), {base});
}

// One free-floating link whose centre of mass is off its origin and whose inertia is not diagonal.
constexpr const char* kSingleBodyUrdf = R"(<robot name="block">
  <link name="block">
    <inertial><origin xyz="0.2 -0.1 0.05"/><mass value="3.0"/>
      <inertia ixx="0.4" ixy="0.05" ixz="-0.02" iyy="0.3" iyz="0.01" izz="0.2"/></inertial>
  </link>
</robot>)";

TEST(MotionMetrics, RigidBodyTurningAtConstantRateKeepsItsKineticEnergy) {
  const Model model = LoadUrdfText("block", kSingleBodyUrdf, FloatingBase::kFree);
  ASSERT_EQ(model.nq(), 7);
  const double rate = 2.5;  // rad/s about ground Z through the link origin
  std::vector<double> time, q, u;
  for (int k = 0; k <= 200; ++k) {
    const double t = k / 100.0;
    time.push_back(t);
    q.insert(q.end(), {std::cos(rate * t / 2), 0, 0, std::sin(rate * t / 2), 0.1, 0.2, 0.3});
    u.insert(u.end(), {0, 0, rate, 0, 0, 0});
  }
  MotionEvaluator evaluator(model, {}, 1000.0, {});
  RangeMetrics whole;
  (void)evaluator.evaluate(time, q, u, {}, 0.0, &whole);
  EXPECT_EQ(whole.eval_frames, 2001);
  // KE = ½ m |ω × R c|² + ½ ωᵀ R I_c Rᵀ ω: both terms are invariant under rotation about ω.
  const double expected_ke = 0.5 * 3.0 * rate * rate * (0.2 * 0.2 + 0.1 * 0.1) + 0.5 * rate * rate * 0.2;
  EXPECT_NEAR(whole.mean_kinetic_energy, expected_ke, 1e-9 * expected_ke);
  EXPECT_LT(whole.mean_delta_ke, 1e-12 * expected_ke);
  EXPECT_GT(whole.mean_delta_p, 0.0);  // the linear momentum turns with the body
  EXPECT_EQ(whole.mean_power, 0.0);    // a free base is not actuated: its residual wrench is excluded
}

// A point-like bob on a horizontal-axis pin: a pendulum welded to the ground.
constexpr const char* kPendulumUrdf = R"(<robot name="pendulum">
  <link name="base"/>
  <link name="bob">
    <inertial><origin xyz="0.7 0 0"/><mass value="2.0"/><inertia ixx="1e-6" iyy="1e-6" izz="1e-6" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <joint name="swing" type="continuous"><parent link="base"/><child link="bob"/><axis xyz="0 1 0"/></joint>
</robot>)";

TEST(MotionMetrics, PendulumAtConstantRateHasTheGravityTorquePower) {
  const Model model = LoadUrdfText("pendulum", kPendulumUrdf, FloatingBase::kFixed);
  ASSERT_EQ(model.nu(), 1);
  const double omega = 3.0, mass = 2.0, length = 0.7, g = model.gravity();
  std::vector<double> time, q, u;
  for (int k = 0; k <= 120; ++k) {
    const double t = k / 60.0;
    time.push_back(t);
    q.push_back(omega * t);
    u.push_back(omega);
  }
  MotionEvaluator evaluator(model, {}, 1000.0, {});
  RangeMetrics whole;
  (void)evaluator.evaluate(time, q, u, {}, 0.0, &whole);
  // No inertial torque at constant rate: τ = m g L cos θ, power |τ ω| per kilogram of the whole robot.
  double expected = 0;
  for (int k = 0; k <= 2000; ++k) expected += mass * g * length * std::abs(std::cos(omega * k / 1000.0)) * omega / mass;
  expected /= 2001;
  EXPECT_NEAR(whole.mean_power, expected, 1e-9 * expected);
}

TEST(MotionMetrics, VirtualBaseChainsAndFreeBasesAreNotActuated) {
  const Model g1 = Model::Load(testing::SourcePath(testing::kG1Urdf));
  int unactuated = 0;
  for (bool actuated : g1.actuatedVelocities()) unactuated += !actuated;
  EXPECT_EQ(unactuated, 6);
  SYN_REQUIRE_SHARED("robots/humanoid_synergies/HRP4c_optitrack_model.urdf");
  const Model hrp4c = Model::Load(testing::SharedPath("robots/humanoid_synergies/HRP4c_optitrack_model.urdf"));
  ASSERT_FALSE(hrp4c.hasFreeBase());
  std::vector<std::string> unactuated_names;
  for (int v = 0; v < hrp4c.nu(); ++v) {
    if (!hrp4c.actuatedVelocities()[static_cast<size_t>(v)]) unactuated_names.push_back(hrp4c.velocityNames()[static_cast<size_t>(v)]);
  }
  EXPECT_EQ(unactuated_names, (std::vector<std::string>{"floating_base_p1", "floating_base_p2", "floating_base_p3",
                                                        "floating_base_r1", "floating_base_r2", "floating_base_r3"}));
}

TEST(FootSliding, SyntheticFeetGiveTheirKnownFraction) {
  const int frames = 1000;
  const double dt = 0.001;
  std::vector<std::vector<FootSample>> feet(2, std::vector<FootSample>(frames));
  for (int k = 0; k < frames; ++k) {
    // Foot 0 moves at 1 m/s throughout: on the ground (1 cm) for frames 0–299, lifted for 300–699, 2 cm
    // into the ground for 700–799 (beyond the 1 cm tolerance), 6 cm up (above contact) for 800–999.
    const double height = k < 300 ? 0.01 : k < 700 ? 0.2 : k < 800 ? -0.02 : 0.06;
    feet[0][k] = {1.0 * k * dt, 0.3, height};
    // Foot 1 stands still on the ground, 5 mm in (within tolerance), and 5 cm in for frames 900–949.
    feet[1][k] = {0.0, -0.1, (k >= 900 && k < 950) ? -0.05 : -0.005};
  }
  const std::vector<uint8_t> sliding = FindSlidingFrames(feet, dt, {});
  int count = 0;
  for (int k = 0; k < frames; ++k) {
    const bool expected = k < 300 || (k >= 700 && k < 800) || (k >= 900 && k < 950);
    EXPECT_EQ(sliding[static_cast<size_t>(k)] != 0, expected) << "frame " << k;
    count += sliding[static_cast<size_t>(k)];
  }
  EXPECT_EQ(count, 450);

  // The same on-ground foot at 0.4 m/s does not slide at the default 0.5 m/s.
  for (int k = 0; k < frames; ++k) feet[0][k] = {0.4 * k * dt, 0.3, 0.0};
  for (int k = 0; k < frames; ++k) feet[1][k].lowest_z = 0.0;
  const std::vector<uint8_t> slow = FindSlidingFrames(feet, dt, {});
  EXPECT_EQ(std::count(slow.begin(), slow.end(), 1), 0);
}

class RealMonteCarlo : public ::testing::Test {
 protected:
  void SetUp() override {
    motion_ = &testing::DemoMotionOnG1("05_02");
    model_ = Model::Load(testing::SourcePath(testing::kG1Urdf));
    boundaries_ = SegmentMotion(*motion_, *model_, {}).boundaries;
    ASSERT_GE(boundaries_.size(), 3u);
  }
  std::vector<double> SegmentTimes(const TrialSynergies::Segment& segment) const {
    return {motion_->time_s.begin() + segment.start_frame, motion_->time_s.begin() + segment.end_frame};
  }
  const MotionData* motion_ = nullptr;
  std::optional<Model> model_;
  std::vector<int64_t> boundaries_;
};

TEST_F(RealMonteCarlo, FullRankReconstructionGivesTheOriginalMetricsBack) {
  SynergyOptions options;
  options.components = 1000;
  const TrialSynergies trial = ComputeTrialSynergies(*motion_, boundaries_, options);
  RobotMap map = LoadRobotMap(testing::SourcePath(testing::kG1Map));
  MotionEvaluator evaluator(*model_, FeetOnModel(map, *model_), 1000.0, {});
  MonteCarloOptions mc;
  mc.samples = 0;
  for (size_t s = 0; s < 2; ++s) {
    const TrialSynergies::Segment& segment = trial.segments[s];
    const MonteCarloSummary summary =
        RunSegmentMonteCarlo(evaluator, segment, SegmentTimes(segment), true, motion_->time_s.front(), s, mc);
    ASSERT_GT(summary.original.eval_frames, 100);
    for (auto field : {&RangeMetrics::mean_delta_p, &RangeMetrics::mean_delta_ke, &RangeMetrics::mean_power,
                       &RangeMetrics::mean_kinetic_energy}) {
      EXPECT_LT(std::abs(summary.rank_k.*field / summary.original.*field - 1.0), 1e-9) << "segment " << s;
    }
    EXPECT_EQ(summary.rank_k.foot_sliding_ratio, summary.original.foot_sliding_ratio);
  }
}

TEST_F(RealMonteCarlo, SameSeedSameNumbersAndRankThreeChangesTheMetrics) {
  const TrialSynergies trial = ComputeTrialSynergies(*motion_, boundaries_, {});
  MotionEvaluator evaluator(*model_, {}, 500.0, {});
  const TrialSynergies::Segment& segment = trial.segments[0];
  MonteCarloOptions mc;
  mc.samples = 4;
  auto run = [&](uint64_t seed) {
    mc.seed = seed;
    return RunSegmentMonteCarlo(evaluator, segment, SegmentTimes(segment), true, motion_->time_s.front(), 0, mc);
  };
  const MonteCarloSummary first = run(1), again = run(1), other = run(2);
  EXPECT_EQ(first.ToJson().dump(), again.ToJson().dump());
  EXPECT_NE(first.samples[0].mean_delta_p, other.samples[0].mean_delta_p);
  // Three synergies of a dance segment leave out real motion: the metrics move.
  EXPECT_GT(std::abs(first.rank_k.mean_delta_ke / first.original.mean_delta_ke - 1.0), 1e-3);
}

// syn-evaluate's base residual is the retargeted motion's own unexplained wrench and contact forces,
// recomputed here from the file (magnitudes, their mean and nearest-rank 95th percentile).
TEST(BaseResidual, ReportsTheMotionsUnexplainedWrench) {
  const MotionData& motion = testing::DemoMotionOnG1("02_01");
  ASSERT_FALSE(motion.unexplained_wrench.empty());
  const Model model = Model::Load(testing::SourcePath(testing::kG1Urdf));
  const nlohmann::json metrics = EvaluateMotion(motion, model, {}, nullptr, EvaluateOptions{}, "");
  const nlohmann::json& reported = metrics["trial"]["base_residual"];
  std::vector<double> force, moment;
  double vertical = 0;
  for (int64_t t = 0; t < motion.frames(); ++t) {
    const double* w = &motion.unexplained_wrench[static_cast<size_t>(t) * 6];
    moment.push_back(std::sqrt(w[0] * w[0] + w[1] * w[1] + w[2] * w[2]));
    force.push_back(std::sqrt(w[3] * w[3] + w[4] * w[4] + w[5] * w[5]));
    for (size_t f = 0; f < motion.contact_feet.size(); ++f) {
      vertical += motion.contact_force[(static_cast<size_t>(t) * motion.contact_feet.size() + f) * 3 + 2];
    }
  }
  const double frames = static_cast<double>(motion.frames());
  double mean_force = 0, mean_moment = 0;
  for (size_t i = 0; i < force.size(); ++i) mean_force += force[i] / frames, mean_moment += moment[i] / frames;
  std::sort(force.begin(), force.end());
  EXPECT_NEAR(reported["mean_unexplained_force_n"].get<double>(), mean_force, 1e-9 * mean_force);
  EXPECT_NEAR(reported["mean_unexplained_moment_nm"].get<double>(), mean_moment, 1e-9 * mean_moment);
  const double p95_force = force[static_cast<size_t>(0.95 * (frames - 1) + 0.5)];  // common/percentile.h's rank
  EXPECT_NEAR(reported["p95_unexplained_force_n"].get<double>(), p95_force, 1e-9 * p95_force);
  EXPECT_NEAR(reported["mean_vertical_contact_force_per_weight"].get<double>(),
              vertical / frames / (motion.total_mass * 9.80665), 1e-9);
}

}  // namespace
}  // namespace syn
