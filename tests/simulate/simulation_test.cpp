// syn-simulate on the real G1 and a real CMU walk: the dynamics integrate conservatively, and the
// controller reproduces the kinematic mapping.
#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <limits>
#include <map>
#include <random>
#include <sstream>
#include <string>

#include <gtest/gtest.h>

#include "common/error.h"
#include "common/model.h"
#include "common/percentile.h"
#include "common/robot_map.h"
#include "stages/simulate/fixed_step_integrator.h"
#include "stages/simulate/simulation.h"
#include "tests/support/cmu_index.h"
#include "tests/support/demo_motion.h"
#include "tests/support/independent_fk.h"
#include "tests/support/shared_data.h"
#include "tests/support/synthetic_motions.h"

namespace syn {
namespace {

using testing::DemoMotionOnG1;
using testing::SourcePath;

// Controller off, no gravity, no contact: a tumbling G1 with every joint moving keeps its kinetic energy.
double RelativeEnergyDrift(Integrator integrator) {
  ModelOptions options;
  options.gravity = 0.0;
  const Model model = Model::Load(SourcePath(testing::kG1Urdf), options);
  Workspace workspace(model);
  std::mt19937 random(3);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::VectorXd q = model.defaultQ(), u(model.nu());
  for (int i = 7; i < model.nq(); ++i) q[i] = 0.5 * uniform(random);
  for (int i = 0; i < model.nu(); ++i) u[i] = uniform(random);  // rad/s and m/s: a brisk motion
  workspace.setQ(q);
  workspace.setU(u);
  const double initial = workspace.calcKineticEnergy();
  FixedStepIntegrator stepper(model);
  const Eigen::VectorXd no_torque = Eigen::VectorXd::Zero(model.nu());
  double worst = 0;
  for (int step = 0; step < 1000; ++step) {  // 1 s at 1 kHz
    stepper.step(workspace, integrator, no_torque, 1e-3, nullptr, q, u);
    workspace.setQ(q);
    workspace.setU(u);
    worst = std::max(worst, std::abs(workspace.calcKineticEnergy() - initial) / initial);
  }
  return worst;
}

TEST(Simulate, KineticEnergyConservedWithoutControlGravityOrContact) {
  const double rk4 = RelativeEnergyDrift(Integrator::kRungeKutta4);
  EXPECT_LT(rk4, 1e-6);
  // Semi-implicit Euler, the stage's default for speed: symplectic, its energy error is O(h) and bounded.
  const double euler = RelativeEnergyDrift(Integrator::kSemiImplicitEuler);
  EXPECT_LT(euler, 1e-2);
  std::cout << "relative kinetic-energy drift over 1 s at 1 kHz: rk4 " << rk4 << ", euler " << euler << "\n";
}

// The paper's mode on a real retargeted CMU walk. Without torque limits the controller reproduces the
// kinematic mapping within 3° RMS, and the knees stay on their side of the straight-leg limit (without
// the walls the right knee was carried 50° onto the mirrored branch). With G1's URDF limits the kinematic
// walk itself needs up to 107 N·m at the waist roll and 134 N·m at the waist pitch (their limit: 50), so
// the torso lags while they clip; the other joints are re-solved around them (2.3° here, was 18°).
TEST(Simulate, PaperModeReproducesKinematicWalk) {
  const MotionData& walk = DemoMotionOnG1("02_01");
  const Model model = Model::Load(SourcePath(testing::kG1Urdf));
  const RobotMap map = LoadRobotMap(SourcePath(testing::kG1Map));
  SimulateOptions unlimited;
  unlimited.controller.effort_limits = false;
  const SimulationResult result = Simulate(walk, "02_01", model, map, unlimited);
  std::cout << "no effort limits: " << result.summary.FullReport() << "\n";
  EXPECT_LE(result.summary.joint_rms_deg, 3.0);
  EXPECT_LT(result.summary.p1_position_rms_m, 0.002);
  EXPECT_EQ(result.summary.saturated_steps, 0);
  for (const ModelJoint& joint : model.joints()) {
    if (joint.name.find("knee") == std::string::npos) continue;
    for (int64_t t = 0; t < result.motion.frames(); ++t) {
      const double angle = result.motion.q[static_cast<size_t>(t * model.nq() + joint.q_index)];
      ASSERT_GT(angle, model.qLower()[joint.q_index] - 0.01) << joint.name << " frame " << t;
    }
  }
  ASSERT_EQ(result.motion.frames(), walk.frames());
  EXPECT_EQ(result.motion.time_s, walk.time_s);
  // The output is the simulation: its first frame is the input's state, and later frames differ.
  EXPECT_EQ(result.motion.q[7], walk.q[7]);
  double difference = 0;
  for (size_t i = 0; i < walk.q.size(); ++i) difference = std::max(difference, std::abs(result.motion.q[i] - walk.q[i]));
  EXPECT_GT(difference, 0.0);
  // Landmark errors are measured wherever the input had a target.
  for (size_t i = 0; i < walk.landmark_error.size(); ++i) {
    if (std::isfinite(walk.landmark_error[i])) {
      EXPECT_TRUE(std::isfinite(result.motion.landmark_error[i])) << i;
    }
  }

  const SimulationResult limited = Simulate(walk, "02_01", model, map, SimulateOptions{});
  std::cout << "URDF effort limits: " << limited.summary.FullReport() << "\n";
  EXPECT_GT(limited.summary.saturated_steps, 0);
  EXPECT_LT(limited.summary.joint_rms_deg, 5.0);
  for (double tau : limited.motion.tau) ASSERT_TRUE(std::isfinite(tau));
}

// Ground mode with balance leaves the base's translation to the centre-of-mass level: the pelvis's pose
// task keeps its orientation rows only, every other task as the map has it; paper mode and ground mode
// without balance solve the map's tasks unchanged.
TEST(Simulate, GroundModeLeavesThePelvisTranslationToTheBalanceLevel) {
  const MotionData& walk = DemoMotionOnG1("02_01");
  const Model model = Model::Load(SourcePath(testing::kG1Urdf));
  const RobotMap map = LoadRobotMap(SourcePath(testing::kG1Map));
  const std::vector<ControlledTask> tasks = BindTasks(map, model, walk);
  const int pelvis = model.findLinkIndex("pelvis");
  ASSERT_EQ(model.freeBaseLink(), pelvis);
  const auto pelvis_task = std::find_if(tasks.begin(), tasks.end(), [&](const ControlledTask& task) { return task.link == pelvis; });
  ASSERT_NE(pelvis_task, tasks.end());
  ASSERT_EQ(pelvis_task->type, TaskType::kPose);
  SimulateOptions paper, ground, unbalanced;
  ground.contact = unbalanced.contact = ContactMode::kGround;
  unbalanced.balance = false;
  for (const SimulateOptions* options : {&paper, &ground, &unbalanced}) {
    const std::vector<ControlledTask> solved = ControllerTasks(tasks, model, *options);
    ASSERT_EQ(solved.size(), tasks.size());
    for (size_t i = 0; i < tasks.size(); ++i) {
      SCOPED_TRACE(tasks[i].landmark);
      EXPECT_EQ(solved[i].landmark, tasks[i].landmark);
      EXPECT_EQ(solved[i].link, tasks[i].link);
      EXPECT_EQ(solved[i].priority, tasks[i].priority);
      const bool dropped = options == &ground && tasks[i].link == pelvis;
      EXPECT_EQ(solved[i].type, dropped ? TaskType::kOrientation : tasks[i].type);
    }
  }
}

// The per-task account of the rows the hierarchy kept (`-v`'s "hierarchy:" line) against the hierarchy's
// own rank: at each priority the kept bits of its tasks add up to the rows that level kept, an orientation
// task reports only rotation bits; and over a simulated walk every task is counted at every control step
// (paper mode: no held feet to leave out), its kept rows never more than it has.
TEST(Simulate, KeptTaskRowsAddUpToEachLevelsRank) {
  const MotionData& walk = DemoMotionOnG1("02_01");
  const Model model = Model::Load(SourcePath(testing::kG1Urdf));
  const RobotMap map = LoadRobotMap(SourcePath(testing::kG1Map));
  const std::vector<ControlledTask> tasks = BindTasks(map, model, walk);
  OperationalSpaceController controller(model, tasks, ControllerOptions{});
  TaskReferences references(walk, model, tasks, TargetSource::kKinematic);
  std::vector<TaskReference> task_references;
  PostureReference posture;
  Workspace workspace(model);
  Eigen::VectorXd tau(model.nu());
  std::map<int, size_t> level_of_priority;
  for (const ControlledTask& task : tasks) level_of_priority[task.priority] = 0;
  size_t next = controller.levelCount() - level_of_priority.size();  // the task levels come last
  for (auto& [priority, level] : level_of_priority) level = next++;
  int dropped = 0;
  for (const int64_t frame : {int64_t{0}, walk.frames() / 3, walk.frames() - 1}) {
    const size_t nq = static_cast<size_t>(model.nq()), nu = static_cast<size_t>(model.nu());
    workspace.setQ(Eigen::Map<const Eigen::VectorXd>(&walk.q[static_cast<size_t>(frame) * nq], model.nq()));
    workspace.setU(Eigen::Map<const Eigen::VectorXd>(&walk.u[static_cast<size_t>(frame) * nu], model.nu()));
    references.sample(frame, 0.0, task_references, posture);
    (void)controller.calcTorques(workspace, task_references, posture, tau);
    std::map<int, int> kept_bits;
    for (size_t i = 0; i < tasks.size(); ++i) {
      const unsigned kept = controller.keptTaskRows(i);
      if (tasks[i].type == TaskType::kOrientation) {
        EXPECT_EQ(kept & ~0x07u, 0u) << tasks[i].landmark;
      }
      const int bits = __builtin_popcount(kept);
      kept_bits[tasks[i].priority] += bits;
      dropped += (tasks[i].type == TaskType::kPose ? 6 : 3) - bits;
    }
    for (const auto& [priority, level] : level_of_priority) {
      EXPECT_EQ(kept_bits[priority], controller.hierarchy().keptRank(level)) << "priority " << priority << ", frame " << frame;
    }
  }
  EXPECT_GT(dropped, 0) << "G1's 33 rows at priority 1 are more than its joints can keep independent";

  const SimulationResult result = Simulate(walk, "02_01", model, map, SimulateOptions{});
  ASSERT_EQ(result.summary.task_rows.size(), tasks.size());
  for (size_t i = 0; i < tasks.size(); ++i) {
    const SimulateSummary::TaskRowsKept& tally = result.summary.task_rows[i];
    EXPECT_EQ(tally.task, tasks[i].landmark);
    // One control call per integration step, and one at the last frame, which is recorded, not stepped.
    EXPECT_EQ(tally.steps, result.summary.steps + 1) << tally.task;
    for (size_t r = 0; r < 6; ++r) {
      EXPECT_LE(tally.kept[r], tally.steps);
      if (!((tally.rows >> r) & 1u)) {
        EXPECT_EQ(tally.kept[r], 0) << tally.task << " row " << r;
      }
    }
  }
  EXPECT_NE(result.summary.FullReport().find("hierarchy: rows kept per control step"), std::string::npos);
}

TEST(Simulate, SameInputsGiveIdenticalOutputs) {
  const MotionData& walk = DemoMotionOnG1("02_01");
  MotionData excerpt = walk;
  const int64_t frames = 60;
  excerpt.time_s.resize(frames);
  excerpt.q.resize(static_cast<size_t>(frames * walk.nq()));
  for (auto* values : {&excerpt.u, &excerpt.udot, &excerpt.tau}) values->resize(static_cast<size_t>(frames * walk.nu()));
  excerpt.landmark_targets.resize(static_cast<size_t>(frames) * walk.landmark_names.size() * 7);
  excerpt.landmark_error.resize(static_cast<size_t>(frames) * walk.landmark_names.size() * 2);
  const Model model = Model::Load(SourcePath(testing::kG1Urdf));
  const RobotMap map = LoadRobotMap(SourcePath(testing::kG1Map));
  const SimulationResult first = Simulate(excerpt, "02_01", model, map, SimulateOptions{});
  const SimulationResult second = Simulate(excerpt, "02_01", model, map, SimulateOptions{});
  EXPECT_EQ(first.motion.q, second.motion.q);
  EXPECT_EQ(first.motion.tau, second.motion.tau);
}

}  // namespace
}  // namespace syn

namespace syn {
namespace {

// The ground-mode tests: G1 with its robot map, contact mode ground.
class PaperMode : public ::testing::Test {
 protected:
  const Model model = Model::Load(SourcePath(testing::kG1Urdf));
  const RobotMap map = LoadRobotMap(SourcePath("manifests/robots/g1.toml"));
};

class GroundMode : public ::testing::Test {
 protected:
  GroundMode() { options.contact = ContactMode::kGround; }
  const Model model = Model::Load(SourcePath(testing::kG1Urdf));
  const RobotMap map = LoadRobotMap(SourcePath("manifests/robots/g1.toml"));
  SimulateOptions options;
};

// Whether `input` (its contact flags) plants the foot of `side` at frame t; false where it has no such foot.
bool SourcePlants(const MotionData& input, const std::string& side, int64_t t) {
  for (size_t c = 0; c < input.contact_feet.size(); ++c) {
    if (input.contact_feet[c] == side) return input.contact[static_cast<size_t>(t) * input.contact_feet.size() + c] != 0;
  }
  return false;
}

// Of the recorded frames where `input` plants a foot and the simulated `output` has it touching the floor,
// the fraction whose sole (its link's x-y plane, the robot map's sole points sharing their z) is more than 3°
// off flat: from the URDF by the tests' own forward kinematics, not the stage's.
double TiltedStanceFraction(const RobotMap& map, const MotionData& input, const MotionData& output) {
  const testing::IndependentFk fk(SourcePath(testing::kG1Urdf));
  int64_t held = 0, tilted = 0;
  const size_t feet = output.contact_feet.size();
  for (int64_t t = 0; t < output.frames(); ++t) {
    const std::map<std::string, Eigen::Isometry3d> poses =
        fk.poses(output.coordinate_names, &output.q[static_cast<size_t>(t * output.nq())], true);
    for (size_t f = 0; f < feet && f < map.feet.size(); ++f) {
      if (!SourcePlants(input, map.feet[f].side, t) || output.contact[static_cast<size_t>(t) * feet + f] == 0) continue;
      ++held;
      const Eigen::Vector3d normal = poses.at(map.feet[f].link).linear().col(2);
      if (std::acos(std::clamp(normal.z(), -1.0, 1.0)) > 3.0 * M_PI / 180.0) ++tilted;
    }
  }
  return held > 0 ? static_cast<double>(tilted) / static_cast<double>(held) : 0.0;
}

// The source's touchdowns after a swing: per map foot, the frames it plants that foot after a frame it
// did not (the stepping aims every swing that ends in one).
int64_t SourceTouchdowns(const RobotMap& map, const MotionData& input) {
  int64_t touchdowns = 0;
  for (const RobotFoot& foot : map.feet) {
    for (int64_t t = 1; t < input.frames(); ++t) touchdowns += SourcePlants(input, foot.side, t) && !SourcePlants(input, foot.side, t - 1) ? 1 : 0;
  }
  return touchdowns;
}

// Over each contact phase of the source (frames it plants a foot) whose foot the simulated record has on
// the floor: how far the sole turned about the vertical (deg) and its centre moved horizontally (mm) from
// the phase's first frame on the floor, as StanceFeet::PhaseDrift measures at the control rate; here at
// the recorded frames, by the tests' own forward kinematics. Returns the per-phase turns and moves.
struct RecordedPhaseDrift {
  std::vector<double> turns_deg, moves_mm;
  // Per phase: the sole's heading at its first recorded frame on the floor against the reference foot's
  // (the input's q) at the phase's first planted frame, either way (deg).
  std::vector<double> landing_turns_deg;
};
RecordedPhaseDrift HeldPhaseDrift(const RobotMap& map, const MotionData& input, const MotionData& output) {
  const testing::IndependentFk fk(SourcePath(testing::kG1Urdf));
  RecordedPhaseDrift drift;
  const size_t feet = std::min(output.contact_feet.size(), map.feet.size());
  struct Phase {
    Eigen::Vector3d centre_local = Eigen::Vector3d::Zero();
    bool held = false;
    int64_t touchdown = -1;  // the phase's first planted frame
    Eigen::Vector2d start = Eigen::Vector2d::Zero();
    double start_yaw = 0, turn = 0, move = 0;
  };
  const auto heading = [](const Eigen::Isometry3d& pose) { return std::atan2(pose.linear()(1, 0), pose.linear()(0, 0)); };
  std::vector<Phase> phases(feet);
  for (size_t f = 0; f < feet; ++f) {
    for (const std::array<double, 3>& p : map.feet[f].sole_points) phases[f].centre_local += Eigen::Vector3d(p[0], p[1], p[2]);
    phases[f].centre_local /= static_cast<double>(map.feet[f].sole_points.size());
  }
  for (int64_t t = 0; t <= output.frames(); ++t) {
    std::map<std::string, Eigen::Isometry3d> poses;  // this frame's, computed once if a foot needs them
    for (size_t f = 0; f < feet; ++f) {
      Phase& phase = phases[f];
      const bool planted = t < output.frames() && SourcePlants(input, map.feet[f].side, t);
      if (!planted) {
        if (phase.held) drift.turns_deg.push_back(phase.turn * 180 / M_PI), drift.moves_mm.push_back(phase.move * 1000);
        phase.held = false;
        phase.touchdown = -1;
        continue;
      }
      if (phase.touchdown < 0) phase.touchdown = t;
      const bool touching = output.contact[static_cast<size_t>(t) * output.contact_feet.size() + f] != 0;
      if (!phase.held && !touching) continue;
      if (poses.empty()) poses = fk.poses(output.coordinate_names, &output.q[static_cast<size_t>(t * output.nq())], true);
      const Eigen::Isometry3d& pose = poses.at(map.feet[f].link);
      const Eigen::Vector2d centre = (pose * phase.centre_local).head<2>();
      const double yaw = heading(pose);
      if (!phase.held) {
        phase.held = true, phase.start = centre, phase.start_yaw = yaw, phase.turn = phase.move = 0;
        const Eigen::Isometry3d reference =
            fk.poses(input.coordinate_names, &input.q[static_cast<size_t>(phase.touchdown * input.nq())], true).at(map.feet[f].link);
        drift.landing_turns_deg.push_back(std::abs(std::remainder(yaw - heading(reference), 2 * M_PI)) * 180 / M_PI);
      }
      phase.turn = std::max(phase.turn, std::abs(std::remainder(yaw - phase.start_yaw, 2 * M_PI)));
      phase.move = std::max(phase.move, (centre - phase.start).norm());
    }
  }
  return drift;
}

// Ground mode on a robot asked to stand: it stays up, its soles stay within 1 cm of the floor, the
// ground carries its weight (the feet's vertical forces sum to m g within 5 % once settled), and the
// balance controller keeps its posture (joint RMS under 0.5°; a version that also held the feet and
// the angular momentum above the tasks left the wrists 31° off).
TEST_F(GroundMode, StandingRobotStaysUpOnItsSoles) {
  const MotionData motion = testing::StandingMotion(model, map, 1.0);
  const SimulationResult result = Simulate(motion, "standing", model, map, options);
  EXPECT_GT(result.summary.lowest_pelvis_ratio, 0.95);
  EXPECT_LT(result.summary.deepest_penetration_mm, 10.0);
  EXPECT_LT(result.summary.joint_rms_deg, 0.5);
  const size_t feet = map.feet.size(), last = result.motion.time_s.size() - 1;
  double vertical = 0;
  for (size_t f = 0; f < feet; ++f) vertical += result.motion.contact_force[(last * feet + f) * 3 + 2];
  EXPECT_NEAR(vertical, model.totalMass() * 9.81, 0.05 * model.totalMass() * 9.81);
  // Standing, the held soles stay flat (both by the stage's count and by independent FK of the record).
  EXPECT_GT(result.summary.held_foot_steps, 0);
  EXPECT_LE(result.summary.tilted_foot_steps, result.summary.held_foot_steps / 100);
  EXPECT_LE(TiltedStanceFraction(map, motion, result.motion), 0.01);
  // Both feet held through one contact phase each, and kept where they stood.
  EXPECT_EQ(result.summary.held_phases, 2);
  EXPECT_LT(result.summary.held_turn_max_deg, 0.5);
  EXPECT_LT(result.summary.held_move_max_mm, 1.0);
  std::cout << "standing 1 s on the ground: held feet turned up to " << result.summary.held_turn_max_deg << " deg and moved up to "
            << result.summary.held_move_max_mm << " mm; lowest pelvis " << result.summary.lowest_pelvis_ratio * 100
            << " %, deepest sole " << result.summary.deepest_penetration_mm << " mm, final vertical force " << vertical
            << " N (weight " << model.totalMass() * 9.81 << " N)\n";
}

// The same stance with the elbows bent and the arms barely moving. When two planted feet shared the
// planned load by whichever vertex the non-negative fit landed on, the joint torques jumped with it
// between steps (hip torques ±45 N·m), a toe slammed into the floor and the vertical force peaked at
// 27 kN, 11.6 mm deep. The least-norm split keeps the forces near the weight.
TEST_F(GroundMode, ForcesStayNearTheWeightWhileTheArmsMove) {
  const MotionData motion = testing::StandingMotion(model, map, 1.0, 0.001);
  const SimulationResult result = Simulate(motion, "standing, arms bent", model, map, options);
  const double weight = model.totalMass() * 9.81;
  EXPECT_LT(result.summary.peak_vertical_force_n, 1.5 * weight);
  EXPECT_LT(result.summary.deepest_penetration_mm, 3.0);
  EXPECT_LT(result.summary.joint_rms_deg, 1.0);
  std::cout << "standing, arms bent: peak vertical force " << result.summary.peak_vertical_force_n << " N (weight "
            << weight << " N), deepest sole " << result.summary.deepest_penetration_mm << " mm, joint RMS "
            << result.summary.joint_rms_deg << " deg\n";
}

// A standing robot shoved sideways at 3 m/s cannot catch itself without stepping: its capture point is
// 0.8 m outside its feet. It falls (pelvis under 60 % of the reference's height) and the stage stops. The
// error carries the frames recorded before the fall (what --fall-record writes): every array cut at the
// same frame, ending before the fall's time, the pelvis already lower and moving sideways.
TEST_F(GroundMode, ReportsAFall) {
  MotionData motion = testing::StandingMotion(model, map, 2.0);
  motion.u[4] = 3.0;  // the first frame's base velocity along y, where the simulation starts
  try {
    (void)Simulate(motion, "sunk", model, map, options);
    ADD_FAILURE() << "no fall reported";
  } catch (const FallError& error) {
    const std::string what = error.what();
    ASSERT_NE(what.find("fell at t = "), std::string::npos) << what;
    const double fell_at = std::stod(what.substr(what.find("fell at t = ") + 12));
    // Why, in the message (fall_diagnosis.h): shoved at its first frame, the standing robot's capture point
    // starts far off the plan, outside its soles, and a standing motion never steps.
    EXPECT_NE(what.find("the capture point was off the balance plan from the start"), std::string::npos) << what;
    EXPECT_NE(what.find("outside the standing soles in 100 % of the frames"), std::string::npos) << what;
    EXPECT_NE(what.find("both feet stayed planted in the source for 100 %"), std::string::npos) << what;
    // Its feet stood where the plan had them: the plan's own zero-moment point stayed on the soles (on the
    // CMU walks that fall, session 33: off them in 89-100 % of the run).
    EXPECT_NE(what.find("the balance plan's own in 0 %"), std::string::npos) << what;
    EXPECT_NE(what.find("the reference itself turned 0 deg over that run"), std::string::npos) << what;
    // A standing take has no steps to count the fall's place among.
    EXPECT_EQ(what.find("of the take's"), std::string::npos) << what;
    const MotionData& record = error.beforeFall();
    const int64_t frames = record.frames(), nq = model.nq(), nu = model.nu();
    ASSERT_GT(frames, 1);
    EXPECT_LT(frames, motion.frames());
    EXPECT_LE(record.time_s.back(), fell_at);
    EXPECT_GT(record.time_s.back(), fell_at - 0.1) << "the record ends at the last frame before the fall";
    EXPECT_EQ(record.q.size(), static_cast<size_t>(frames * nq));
    EXPECT_EQ(record.u.size(), static_cast<size_t>(frames * nu));
    EXPECT_EQ(record.tau.size(), static_cast<size_t>(frames * nu));
    EXPECT_EQ(record.contact.size(), static_cast<size_t>(frames) * map.feet.size());
    EXPECT_EQ(record.contact_force.size(), static_cast<size_t>(frames) * map.feet.size() * 3);
    EXPECT_EQ(record.unexplained_wrench.size(), static_cast<size_t>(frames * 6));
    EXPECT_EQ(record.landmark_error.size(), static_cast<size_t>(frames) * record.landmark_names.size() * 2);
    // The free base's position is q[4..6]: pushed along y, falling.
    const size_t last = static_cast<size_t>((frames - 1) * nq);
    EXPECT_GT(record.q[last + 5] - record.q[5], 0.1);
    EXPECT_LT(record.q[last + 6], record.q[6] - 0.05);
  }
}

}  // namespace
}  // namespace syn


namespace syn {
namespace {

// A take that starts with both soles above the floor (CMU 02_01 starts mid-stride 2 cm up) starts on
// the floor: moved down until its lowest sole point touches, so the robot does not begin by falling.
TEST_F(GroundMode, StartsOnTheFloor) {
  MotionData motion = testing::StandingMotion(model, map, 0.1);
  const double raised = 0.03;
  for (size_t t = 0; t < motion.time_s.size(); ++t) motion.q[t * static_cast<size_t>(model.nq()) + 6] += raised;
  const SimulationResult result = Simulate(motion, "raised", model, map, options);
  EXPECT_NEAR(result.motion.q[6], motion.q[6] - raised, 1e-9);  // the first frame, lowered
  // Its feet carry the weight from the first steps: the first recorded frames after the start touch.
  const size_t feet = map.feet.size();
  EXPECT_TRUE(result.motion.contact[feet] != 0 || result.motion.contact[feet + 1] != 0);
}

}  // namespace
}  // namespace syn

namespace syn {
namespace {

// Capture-point balance: a standing G1 shoved sideways at 0.5 m/s (its capture point 12 cm out, near
// the outer edge of its foot at 15 cm) stands with the balance controller, which moves its zero-moment
// point to that edge and its centre of mass back. Shoved at 1 m/s (25 cm out, past the foot), it cannot
// stand without stepping, and a standing motion has no step to take: the stage reports the fall.
// Since the standing feet are held as a level above the tasks (stance_feet.h, 2026-11-27), the paper's PD
// on the pelvis alone (--no-balance) also stands at 0.5 m/s (before, it fell at 1.2 s), and at 0.6 and
// 0.8 m/s, where the balance controller falls (1.3 and 1.0 s): its centre-of-mass level leaves the body's
// turn to the tasks, and the PD's pelvis, tipping with the feet held, turns the body to recover. On the
// CMU walks the balance plan and stepping keep 4 of 21 up, none without them (issue 18's notes).
TEST_F(GroundMode, BalanceCatchesASideShove) {
  MotionData motion = testing::StandingMotion(model, map, 2.0);
  motion.u[4] = 0.5;  // the first frame's base velocity along y
  const SimulationResult result = Simulate(motion, "shoved", model, map, options);
  EXPECT_GT(result.summary.lowest_pelvis_ratio, 0.95);
  motion.u[4] = 1.0;
  EXPECT_THROW((void)Simulate(motion, "shoved hard", model, map, options), DataError);
  options.balance = false;
  EXPECT_THROW((void)Simulate(motion, "shoved hard, no balance", model, map, options), DataError);
}

// Issue 18's ground mode on every shared CMU walk (index.csv's walk class) retargeted onto G1: how many stay
// up (pelvis never under 60 % of the reference's), printed with each fall's time, and that those that do
// stay inside the URDF's joint ranges (checked on the recorded q). Not every walk yet: on 2026-11-27
// (session 24, with the joints' mechanical stops, joint_stops.h, the contact's dissipation at 1 s/m and the
// balance gain 4 and step cap 0.25 m) 8 of 21 (02_01, 02_02, 07_01, 07_06, 08_01, 08_11, 10_04, 12_03;
// 02_01 and 12_03 stumble, their pelvis down to 74 and 66 % of the reference's), the others falling after
// 0.55-4.2 s. Before the stops (session 23) 4 of 21 also "stayed up" (02_01, 02_02, 07_01, 07_06), but on
// ankle rolls 8-105° past G1's ±15° in 14-40 % of their frames (02_01's left ankle turned round 2.5 times),
// a balance no G1 has. Without stepping (--step-adjustment 0) 2 stay up, without the balance plan
// (--no-balance) none. Which walks stay up changes with any parameter (4-8 over balance gains 2-6 and
// step caps 0.15-0.35 m: balance_controller.h), so the guard is
// below today's count. Subject 03's walks are over uneven terrain, which a flat floor cannot give them.
// Session 26 (swing feet carried 4 cm higher at mid-swing, starts inside the joints' limits): 13 of 21
// (02_01 02_02 06_01 07_01 07_04 07_06 08_01 08_04 08_11 10_04 12_01 12_02 12_03); 10-14 over the 8
// settings of balance_controller.h, mean 13.0 (11.9 before).
// rad: how far past its URDF limit a joint pressing its stop may go. The stops are stiff springs, not
// constraints: on the walks that stay up 0.04-0.9°, and 3.6° on 12_03, which stumbles (its pelvis down to
// 66 % of the reference's) and lands hard on its left ankle roll. Without stops the ankle rolls went
// 8-886° past.
constexpr double kStopTolerance = 4.0 * M_PI / 180.0;
// The largest vertical ground force a walk that stays up may reach, in body weights (a hard landing; the
// walks reached 1.9-4.5 and contact chatter 30-125 when their soles carried planned force only where they
// touched). Measured as the force the linearly implicit step applies: 2.2-4.0 on the 13 walks up
// (2026-11-27). Until then the force evaluated at a step's start was reported, and single steps where a
// sole point came down fast read 8-59 body weights that never acted (CMU 07_06: 20.6 kN read, 1.6 kN
// applied).
constexpr double kPeakForceInWeights = 8.0;

// The farthest any limited joint of `motion` goes past the model's limits over its frames (rad), and a
// description of where.
double WorstLimitExcess(const Model& model, const MotionData& motion, std::string* where = nullptr) {
  double worst = 0.0;
  for (const ModelJoint& joint : model.joints()) {
    if (joint.q_index < 0 || joint.type == "free") continue;
    const double lower = model.qLower()[joint.q_index], upper = model.qUpper()[joint.q_index];
    if (!std::isfinite(lower) || !std::isfinite(upper)) continue;
    for (int64_t t = 0; t < motion.frames(); ++t) {
      const double q = motion.q[static_cast<size_t>(t * motion.nq() + joint.q_index)];
      const double excess = std::max(q - upper, lower - q);
      if (excess > worst) {
        worst = excess;
        if (where) *where = joint.name + " at frame " + std::to_string(t);
      }
    }
  }
  return worst;
}

std::string LimitExcess(const Model& model, const MotionData& motion) {
  std::string where = "every joint inside its limits";
  const double worst = WorstLimitExcess(model, motion, &where);
  return worst > 0 ? std::to_string(worst * 180.0 / M_PI) + " deg past a limit, " + where : where;
}

// The largest difference over the recorded frames between the contact force the motion file reports (both
// feet summed) and the force its own q, u, u̇ need: the free base's translational rows of their inverse
// dynamics, which no joint torque reaches (N). The force the implicit step applied passes this; the force
// evaluated at the step's start before it did not (a 20 kN "peak" where 1.6 kN acted).
double WorstContactForceMismatch(const Model& model, const MotionData& motion) {
  Workspace workspace(model);
  Eigen::VectorXd tau(model.nu());
  const size_t feet = motion.contact_feet.size();
  double worst = 0;
  for (int64_t t = 0; t < motion.frames(); ++t) {
    const size_t frame = static_cast<size_t>(t);
    workspace.setQ(Eigen::Map<const Eigen::VectorXd>(&motion.q[frame * static_cast<size_t>(motion.nq())], motion.nq()));
    workspace.setU(Eigen::Map<const Eigen::VectorXd>(&motion.u[frame * static_cast<size_t>(motion.nu())], motion.nu()));
    workspace.calcInverseDynamics(Eigen::Map<const Eigen::VectorXd>(&motion.udot[frame * static_cast<size_t>(motion.nu())], motion.nu()), tau);
    Eigen::Vector3d reported = Eigen::Vector3d::Zero();
    for (size_t f = 0; f < feet; ++f) reported += Eigen::Map<const Eigen::Vector3d>(&motion.contact_force[(frame * feet + f) * 3]);
    worst = std::max(worst, (tau.segment<3>(3) - reported).norm());
  }
  return worst;
}

// The least vertical force any foot of `motion` carries at a recorded frame (N): the floor never pulls.
double LowestVerticalSoleForce(const MotionData& motion) {
  double lowest = std::numeric_limits<double>::infinity();
  for (size_t i = 2; i < motion.contact_force.size(); i += 3) lowest = std::min(lowest, motion.contact_force[i]);
  return lowest;
}

// The median, over the swings of `input` (unplanted runs between two planted frames, per map foot), of the
// lowest sole point at each swing's middle frame in `output` (m): by the tests' own FK of the record.
double MedianMidSwingClearance(const RobotMap& map, const MotionData& input, const MotionData& output) {
  const testing::IndependentFk fk(SourcePath(testing::kG1Urdf));
  std::vector<double> clearance;
  for (size_t f = 0; f < map.feet.size(); ++f) {
    const auto planted = [&](int64_t t) { return SourcePlants(input, map.feet[f].side, t); };
    for (int64_t t = 1, start = -1; t < input.frames(); ++t) {
      if (!planted(t) && planted(t - 1)) start = t;
      if (planted(t) && !planted(t - 1) && start >= 0) {
        const int64_t middle = (start + t) / 2;
        const Eigen::Isometry3d pose =
            fk.poses(output.coordinate_names, &output.q[static_cast<size_t>(middle * output.nq())], true).at(map.feet[f].link);
        double lowest = std::numeric_limits<double>::infinity();
        for (const std::array<double, 3>& p : map.feet[f].sole_points) lowest = std::min(lowest, (pose * Eigen::Vector3d(p[0], p[1], p[2])).z());
        clearance.push_back(lowest);
        start = -1;
      }
    }
  }
  if (clearance.empty()) return std::nan("");
  std::sort(clearance.begin(), clearance.end());
  return clearance[clearance.size() / 2];
}

// --swing-lift carries a swinging foot higher by lift·sin(π s): at mid-swing the whole lift. On a real walk
// (CMU 07_01, which stays up either way) the simulated soles' mid-swing clearance rises by most of it
// (2026-11-27: median 21 -> 51 mm for 40 mm; the kinematic motion's 20 mm), and without it the simulation
// swings its feet as low as the kinematic motion does (what made heels catch the floor: balance_controller.h).
TEST_F(GroundMode, SwingLiftRaisesTheSwingingFoot) {
#ifdef SYN_SANITIZED_BUILD
  GTEST_SKIP() << "a real-data ground-mode simulation runs in the Release test run, not under the sanitizers";
#endif
  SYN_REQUIRE_SHARED("cmu_bvh/07/07_01.bvh");
  const MotionData walk = testing::CmuBvhOnG1(testing::SharedPath("cmu_bvh/07/07_01.bvh"));
  const double reference = MedianMidSwingClearance(map, walk, walk);
  options.swing_lift = 0.0;
  const double unlifted = MedianMidSwingClearance(map, walk, Simulate(walk, "07_01", model, map, options).motion);
  options.swing_lift = 0.04;
  const double lifted = MedianMidSwingClearance(map, walk, Simulate(walk, "07_01", model, map, options).motion);
  std::printf("07_01 mid-swing clearance (median): kinematic %.1f mm, simulated without lift %.1f mm, with 40 mm %.1f mm\n",
              1000 * reference, 1000 * unlifted, 1000 * lifted);
  EXPECT_NEAR(unlifted, reference, 0.01);
  EXPECT_GT(lifted - unlifted, 0.02);
  EXPECT_LT(lifted - unlifted, 0.06);
}

// The swinging feet's level (OperationalSpaceController::setSwingingFeet: the heading, and the horizontal
// position over the swing's last 30 %): a foot lands at the reference's heading where, left to its task at
// priority 1 (whose yaw row the hierarchy dropped in 60-65 % of the swing's steps), a straightening leg spun
// it. Measured by the tests' own FK of the records, against the reference foot's heading at each source
// touchdown (HeldPhaseDrift). Session 47, three walks that stay up either way: the largest landing turn 1.3
// / 7.7 / 10.0 deg with the level against 13.1 / 18.8 / 18.4 without (07_01, 02_01, 12_02); over three more
// draws with the balance gain moved by 1-5 × 10⁻⁹ of itself (the arithmetic's rounding moves which landing
// is the worst: README, the takes that fall), 1.1-2.7 / 5.4-5.8 / 6.8-8.9 against 7.2-10.4 / 21.0-22.0 /
// 13.4-14.5.
TEST_F(GroundMode, SwingingFeetLandAtTheReferenceHeading) {
#ifdef SYN_SANITIZED_BUILD
  GTEST_SKIP() << "a real-data ground-mode simulation runs in the Release test run, not under the sanitizers";
#endif
  for (const char* name : {"07_01", "02_01", "12_02"}) {
    const std::string file = std::string("cmu_bvh/") + std::string(name, 2) + "/" + name + ".bvh";
    SYN_REQUIRE_SHARED(file);
    const MotionData walk = testing::CmuBvhOnG1(testing::SharedPath(file));
    double largest[2] = {0, 0};
    for (const bool level : {true, false}) {
      options.swing_heading = level;
      const SimulationResult result = Simulate(walk, name, model, map, options);
      const std::vector<double> turns = HeldPhaseDrift(map, walk, result.motion).landing_turns_deg;
      ASSERT_FALSE(turns.empty()) << name;
      largest[level ? 0 : 1] = *std::max_element(turns.begin(), turns.end());
    }
    std::printf("%s: largest landing turn from the reference's heading %.1f deg with the swinging feet's heading level, "
                "%.1f without\n", name, largest[0], largest[1]);
    EXPECT_LT(largest[0], largest[1]) << name;
    EXPECT_LE(largest[0], 12.0) << name;
  }
}

// `--control-trace` (control_trace.h) on the demo's 02_01 in ground mode: a row per control call, and
// tracing changes nothing simulated. Its applied sole forces are the floor's whole push: over the run their
// impulse less the weight's equals the change of the body's momentum, which the test takes from the
// recorded first and last frames' velocities (Simbody's centroidal momentum), not from the trace.
TEST_F(GroundMode, ControlTraceAccountsForTheBodysMomentum) {
  const MotionData& walk = DemoMotionOnG1("02_01");
  const SimulationResult plain = Simulate(walk, "02_01", model, map, options);
  ControlTrace trace;
  const SimulationResult traced = Simulate(walk, "02_01", model, map, options, &trace);
  EXPECT_EQ(traced.motion.q, plain.motion.q) << "tracing changed the simulation";
  EXPECT_EQ(traced.motion.tau, plain.motion.tau) << "tracing changed the simulation";
  const std::vector<ControlTraceRow>& rows = trace.rows();
  ASSERT_EQ(static_cast<int64_t>(rows.size()), traced.summary.steps + 1) << "one row per control call";
  const double weight = model.totalMass() * model.gravity();
  Eigen::Vector3d impulse = Eigen::Vector3d::Zero();
  for (size_t i = 0; i + 1 < rows.size(); ++i) {
    const double dt = rows[i + 1].time - rows[i].time;
    ASSERT_GT(dt, 0) << "row " << i;
    impulse += dt * (rows[i].applied_force - Eigen::Vector3d(0, 0, weight));
    if (rows[i].balancing) {
      EXPECT_GE(rows[i].level.force.z(), 0.2 * weight - 1e-9) << "row " << i;
      EXPECT_LE(rows[i].level.force.z(), 3.0 * weight + 1e-9) << "row " << i;
    }
  }
  EXPECT_EQ(rows.back().time, walk.time_s.back());
  Workspace workspace(model);
  const auto momentum = [&](int64_t frame) {
    const size_t nq = static_cast<size_t>(model.nq()), nu = static_cast<size_t>(model.nu());
    workspace.setQ(Eigen::Map<const Eigen::VectorXd>(&traced.motion.q[static_cast<size_t>(frame) * nq], model.nq()));
    workspace.setU(Eigen::Map<const Eigen::VectorXd>(&traced.motion.u[static_cast<size_t>(frame) * nu], model.nu()));
    return Eigen::Vector3d(workspace.calcCentroidalMomentum().tail<3>());
  };
  const Eigen::Vector3d change = momentum(walk.frames() - 1) - momentum(0);
  std::printf("02_01 over %.2f s: floor impulse less the weight's (%.3f, %.3f, %.3f) N s, momentum change (%.3f, %.3f, %.3f) N s; "
              "the weight's impulse %.1f N s\n", rows.back().time - rows.front().time, impulse.x(), impulse.y(), impulse.z(), change.x(),
              change.y(), change.z(), weight * (rows.back().time - rows.front().time));
  // Session 47: (9.563, 2.534, -1.191) against (9.493, 2.546, -1.193) N s, the weight's impulse 981 N s.
  EXPECT_GT(change.head<2>().norm(), 5.0) << "a walk that goes somewhere";
  EXPECT_LT((impulse - change).norm(), 0.3);
  // The CSV: a header and a line per row, 29 columns each.
  const std::string csv = trace.ToCsv();
  std::istringstream lines(csv);
  std::string line;
  int64_t count = -1;
  while (std::getline(lines, line)) {
    ++count;
    EXPECT_EQ(std::count(line.begin(), line.end(), ','), 28) << "line " << count;
  }
  EXPECT_EQ(count, static_cast<int64_t>(rows.size()));
}

// Paper mode (a driven base, no floor) on the CMU dances, at the defaults (the URDF's effort limits): the
// simulated robot has its joints' mechanical stops in this mode too (joint_stops.h). Without them, where the
// limited torques let a joint fall behind a fast reference, it turned on past its limits: a shoulder through
// 378-714° (05_02, 05_11, 60_02, 94_07, 94_15; joint RMS to the kinematic motion 35-137°), and 05_20 and 60_10
// diverged. With them every dance completes and every joint stays inside its limits; the joint RMS is still
// 5-23° on 7 of the 11 (the wrists, saturated, swing between their stops), reported, not asserted: issue 18's
// bound is on the walks (PaperModeReproducesKinematicWalk, and all 21 CMU walks within 1°).
TEST_F(PaperMode, CmuDancesStayInsideTheirJointLimits) {
#ifdef SYN_SANITIZED_BUILD
  GTEST_SKIP() << "the real-data paper-mode sweep runs in the Release test run, not under the sanitizers";
#endif
  SYN_REQUIRE_SHARED("cmu_bvh/index.csv");
  const std::vector<testing::CmuTrial> dances = testing::CmuTrials({"dance"});
  for (const testing::CmuTrial& trial : dances) {
    const MotionData dance = testing::CmuBvhOnG1(testing::SharedPath("cmu_bvh/" + trial.file));
    try {
      const SimulationResult result = Simulate(dance, trial.name, model, map, SimulateOptions{});
      std::printf("%s paper mode: joint RMS to the kinematic motion %.2f deg; %s\n", trial.name.c_str(),
                  result.summary.joint_rms_deg, LimitExcess(model, result.motion).c_str());
      EXPECT_LE(WorstLimitExcess(model, result.motion), kStopTolerance) << trial.name << ": a joint past its URDF limit";
    } catch (const DataError& error) {
      ADD_FAILURE() << trial.name << ": " << error.what();
    }
  }
  EXPECT_EQ(dances.size(), 11u);
}

// CMU 07_12, the brisk walk (about 1.1 m/s, arms swinging), falls at the defaults: from its first frames
// the plan asks for tilting moments of 90 N·m median (the walks that stay up: 10-50) that the soles cannot
// give, the fit of the sole forces gives up moment and force one to one, and the body tips over with
// what it could not give (pelvis pitched 37 deg at 0.67 s). With the moments weighted 2 against the
// force (--moment-weight), the centre of mass falls behind the plan instead, which the capture point's
// stepping corrects, and it stays up through its whole take: in 15 of 16 runs with the balance gain moved
// by 1-8e-9 (1 of 16 at the default weight), so this is not one lucky rounding (session 35). Its
// tracking is loose all the same (pelvis ends 0.5 m ahead of the reference, feet landed 20-60 deg off
// their headings; independent FK of the record); the other walks' spread mean is 15.75 at weight 2
// against 15.81 at 1 (SimulateOptions::moment_weight). Since the pelvis's position rows were left to the
// balance level (ControllerTasks, session 44) it stays up at weight 2 in 12 of those 16 runs, its pelvis
// down to 74-94 % of the reference's height in them, 72 % in this draw (until then at least 80 %). With
// the swinging feet's level (session 47) it stays up at weight 2 in 7 of 8 runs of the CLI (one fell 0.02 s
// before the take's end), its pelvis down to 86-93 %, 93 % in this draw.
TEST_F(GroundMode, TheBriskWalkStaysUpWithItsMomentsFavoured) {
#ifdef SYN_SANITIZED_BUILD
  GTEST_SKIP() << "a real-data ground-mode simulation runs in the Release test run, not under the sanitizers";
#endif
  SYN_REQUIRE_SHARED("cmu_bvh/07/07_12.bvh");
  const MotionData walk = testing::CmuBvhOnG1(testing::SharedPath("cmu_bvh/07/07_12.bvh"));
  options.moment_weight = 2.0;
  const SimulationResult result = Simulate(walk, "07_12", model, map, options);
  std::printf("07_12 with the moments weighted 2: %s\n", result.summary.FullReport().c_str());
  EXPECT_GE(result.summary.lowest_pelvis_ratio, 0.7);
  EXPECT_LE(result.summary.deepest_penetration_mm, 10.0);
  EXPECT_LE(result.summary.peak_vertical_force_n, kPeakForceInWeights * model.totalMass() * model.gravity());
  EXPECT_LE(WorstLimitExcess(model, result.motion), kStopTolerance) << "a joint past its URDF limit";
  EXPECT_LE(WorstContactForceMismatch(model, result.motion), 0.01) << "the reported contact forces against inverse dynamics (N)";
  EXPECT_GE(LowestVerticalSoleForce(result.motion), 0.0) << "the floor pulled a foot";
}

TEST_F(GroundMode, SomeCmuWalksStayUp) {
#ifdef SYN_SANITIZED_BUILD
  GTEST_SKIP() << "the real-data ground-mode sweep runs in the Release test run, not under the sanitizers";
#endif
  SYN_REQUIRE_SHARED("cmu_bvh/index.csv");
  const std::vector<testing::CmuTrial> walks = testing::CmuTrials({"walk"});
  int up = 0;
  for (const testing::CmuTrial& trial : walks) {
    const MotionData walk = testing::CmuBvhOnG1(testing::SharedPath("cmu_bvh/" + trial.file));
    try {
      const SimulationResult result = Simulate(walk, trial.name, model, map, options);
      ++up;
      // Held soles more than 3° off flat, on an edge or a corner (2026-11-28: 53-89 % of the held
      // foot-steps of the 8 walks then up; with the planned forces on sole points within 2 cm and the
      // torques that keep the held feet, 14-32 %): reported, and the stage's count checked against
      // independent FK of the recorded frames.
      const double tilted = TiltedStanceFraction(map, walk, result.motion);
      const double counted = static_cast<double>(result.summary.tilted_foot_steps) / static_cast<double>(result.summary.held_foot_steps);
      std::printf("%s: stays up (lowest pelvis %.2f of the reference's; %s; held soles >3 deg off flat in %.0f %% of "
                  "foot-steps, %.0f %% of recorded frames)\n", trial.name.c_str(), result.summary.lowest_pelvis_ratio,
                  LimitExcess(model, result.motion).c_str(), 100 * counted, 100 * tilted);
      EXPECT_NEAR(counted, tilted, 0.1) << trial.name << ": the stage's count of tilted held soles against FK of its record";
      const RecordedPhaseDrift recorded = HeldPhaseDrift(map, walk, result.motion);
      const double recorded_turn = NearestRankPercentile(recorded.turns_deg, 0.5), recorded_move = NearestRankPercentile(recorded.moves_mm, 0.5);
      std::printf("%s: held feet over %lld phases turned %.1f deg median (%.1f at most), moved %.1f mm median (%.1f at most); "
                  "from the record: %zu phases, %.1f deg, %.1f mm\n", trial.name.c_str(), static_cast<long long>(result.summary.held_phases),
                  result.summary.held_turn_median_deg, result.summary.held_turn_max_deg, result.summary.held_move_median_mm,
                  result.summary.held_move_max_mm, recorded.turns_deg.size(), recorded_turn, recorded_move);
      // The stage's measure (at 1 kHz, from the first held step) against the record's (at 120 Hz, from the
      // first recorded frame on the floor, up to 8 ms later). Session 33: the same phase counts, medians
      // within 0.8 deg and 2.1 mm on the 17 walks up. Since a foot at heel-off is held by its toe (session
      // 44) it can turn on its toe for a few ms that the 120 Hz record steps over: turn medians up to 2.6 deg
      // apart (02_02: 13.0 against 10.4; 08_11: 19.9 against 18.0).
      EXPECT_EQ(static_cast<size_t>(result.summary.held_phases), recorded.turns_deg.size()) << trial.name;
      EXPECT_NEAR(result.summary.held_turn_median_deg, recorded_turn, 3.0) << trial.name << ": held feet's turn against FK of the record";
      // Session 47, the swinging feet's horizontal rows through their landing: 07_12's held feet slide in their
      // first ms on the floor, which the record steps over: 16.7 mm against 9.7 (the other walks up within 2.9).
      EXPECT_NEAR(result.summary.held_move_median_mm, recorded_move, 8.0) << trial.name << ": held feet's move against FK of the record";
      // Where the feet landed turned, against the reference's heading at each source touchdown.
      const double recorded_landing = NearestRankPercentile(recorded.landing_turns_deg, 0.5);
      // The record's middle pair (one value for an odd count): with an even count any value between them is a
      // median.
      std::vector<double> landings = recorded.landing_turns_deg;
      ASSERT_FALSE(landings.empty()) << trial.name;
      std::sort(landings.begin(), landings.end());
      const double middle_low = landings[(landings.size() - 1) / 2], middle_high = landings[landings.size() / 2];
      std::printf("%s: landings turned %.1f deg median (%.1f p95, %.1f at most) from the reference's heading; from the record: "
                  "%.1f (middle pair %.1f-%.1f)\n", trial.name.c_str(), result.summary.landing_turn_median_deg,
                  result.summary.landing_turn_p95_deg, result.summary.landing_turn_max_deg, recorded_landing, middle_low, middle_high);
      EXPECT_EQ(result.summary.landings, result.summary.held_phases) << trial.name << ": every walk phase has a source touchdown";
      // The stage measures at the first held step, the record at its first frame on the floor, up to 8 ms
      // later, and a landing foot can spin fast then (06_01's right foot up to 24 rad/s in its first 40 ms on
      // the floor): session 36, medians within 0.4 deg on 16 of the 17 walks up, 2.0 deg apart on 06_01. So the
      // stage's median is checked against the record's middle pair, 3 deg either side: a walk's few landings
      // can fall in two clusters, and then a degree at one landing moves a nearest-rank median across the gap
      // (session 49, 07_12 up in this draw: six landings at about 1 deg and 5-8 deg, the stage's median 1.75
      // and the record's 5.34).
      EXPECT_GE(result.summary.landing_turn_median_deg, middle_low - 3.0) << trial.name << ": landings' turn against FK of the record";
      EXPECT_LE(result.summary.landing_turn_median_deg, middle_high + 3.0) << trial.name << ": landings' turn against FK of the record";
      // Where the feet landed against where the stepping aimed them: one landing per source touchdown after
      // a swing (counted here from the input's contact flags), every swing aimed. Session 37: each walk's
      // median 8.5-42.5 mm, the largest 158 mm (10_04). Session 44, feet at heel-off held by their toe:
      // 07_12, the brisk walk, now up, 86 mm, and 08_07 104 mm; the others 10-60 mm.
      EXPECT_EQ(result.summary.aimed_landings, SourceTouchdowns(map, walk)) << trial.name;
      std::printf("%s: landings %.1f mm median from the stepping's aim (%.1f at most)\n", trial.name.c_str(),
                  result.summary.landing_miss_median_mm, result.summary.landing_miss_max_mm);
      EXPECT_LE(result.summary.landing_miss_median_mm, 110.0) << trial.name;
      EXPECT_LE(WorstLimitExcess(model, result.motion), kStopTolerance) << trial.name << ": a joint past its URDF limit";
      // Issue 18: soles never more than 1 cm into the floor; and no contact chatter (with the contact's
      // dissipation at 10 s/m the soles' force switched between 0 and 20-43 kN every step, 13 mm deep).
      EXPECT_LE(result.summary.deepest_penetration_mm, 10.0) << trial.name;
      EXPECT_LE(result.summary.peak_vertical_force_n, kPeakForceInWeights * model.totalMass() * model.gravity()) << trial.name;
      EXPECT_LE(WorstContactForceMismatch(model, result.motion), 0.01)
          << trial.name << ": the reported contact forces are those the base's inverse dynamics needs (N)";
      // The floor never pulls (ground_contact.h): until session 41, 15 of the 15 walks then up had a foot
      // held down at a lift-off or a hard touchdown, by up to 98 N, in 1 % of their frames.
      EXPECT_GE(LowestVerticalSoleForce(result.motion), 0.0) << trial.name << ": the floor pulled a foot";
      // A walk has a sole on the floor nearly always (08_07: in 293 of its 296 frames); how often the
      // capture-point feedback was short of authority (its zero-moment point clamped onto a sole's edge) is
      // reported (session 32: 29-86 % of the frames).
      EXPECT_GE(result.summary.balancing_frames, 0.95 * static_cast<double>(walk.frames())) << trial.name;
      EXPECT_GE(result.summary.clamped_frames, 0) << trial.name;
      EXPECT_LE(result.summary.clamped_frames, result.summary.balancing_frames) << trial.name;
      EXPECT_GE(result.summary.plan_off_frames, 0) << trial.name;
      EXPECT_LE(result.summary.plan_off_frames, result.summary.balancing_frames) << trial.name;
      std::printf("%s: the feedback's zero-moment point clamped in %.0f %% of the frames, the plan's own off the soles in %.0f %%\n",
                  trial.name.c_str(), 100.0 * static_cast<double>(result.summary.clamped_frames) / static_cast<double>(walk.frames()),
                  100.0 * static_cast<double>(result.summary.plan_off_frames) / static_cast<double>(walk.frames()));
    } catch (const DataError& error) {
      // A fall's message says why (fall_diagnosis.h).
      std::printf("%s: %s\n", trial.name.c_str(), error.what());
      EXPECT_NE(std::string(error.what()).find("the capture point"), std::string::npos) << trial.name;
    }
  }
  std::printf("ground mode: %d of %zu CMU walks stay up\n", up, walks.size());
  EXPECT_EQ(walks.size(), 21u);
  // 2026-11-28: 14 up (8 before the planned forces on sole points within 2 cm and the torques that keep
  // the held feet); over nearby balance settings 11-14 (balance_controller.h).
  // 2026-11-27 (session 27): 15 up, since the BVH reader drops the frame after the reference frame where a
  // joint is still at rest (bvh_reader.cpp): 05_01's right ankle there had begun the simulation with the
  // retargeted body moving 0.84 m/s sideways, and it fell in all 8 balance settings; now it stays up in all
  // 8. Over the 8 settings 12-15, mean 13.75 (12.88 without).
  // 2026-11-27 (session 28): 13 up after the IK's per-joint smoothing (P1 errors within 0.2 mm of before):
  // 03_02, 06_01 and 12_03 fall, 03_01 stays up. Over gain 3-4.5 1/s x cap 0.28-0.3 m, mean 13.75 -> 14.12.
  // 2026-11-27 (session 29): the terrain walks replayed on the flat floor (syn-retarget's terrain
  // flattening): 13 up (the CLI's 12 -> 13, 03_01 up), the 8-setting mean 14.12 -> 13.38 (03_01 up in 1 of 8
  // instead of 3, 03_02 in none instead of 4); 03_02-03_04 fall later (1.96, 3.56, 3.67 s).
  // 2026-11-27 (session 30): the ingest drops 08_07's held lead-in (6 repeated frames, then its hips 9 cm in
  // a frame; bvh_reader.cpp): 08_07 stays up (it fell at 0.63 s, backward, before its first step), 14 up;
  // over the 8 settings 13-16, mean 13.38 -> 14.88 (08_07 up in 8 of 8). 03_02, whose T-pose lead-in the
  // ingest drops too, still falls (2.0 s).
  // 2026-11-27 (session 31): the balance plan keeps its zero-moment point 2.5 cm inside the feet instead
  // of 1 cm (--support-margin; SimulateOptions): 17 up (03_02, 06_01 and 12_03 now stay up; 03_03, 03_04,
  // 07_12 and 09_12 fall at 5.36, 3.26, 1.80 and 3.97 s); over the 8 settings 15-17, mean 14.88 -> 16.25.
  // 2026-11-28 (session 32): the 17 is the top of a spread that rounding alone opens. With the balance gain
  // moved by 1-8e-9 either way (16 runs of syn-simulate) 14-17 stay up, mean 15.8. This guards the exact
  // arithmetic of this build: a compiler or Eigen that rounds differently may lower it by up to 3 with no
  // change of behaviour; judge such a failure by the spread, not by this one run.
  // 2026-11-28 (session 38): exactly that. The task inertias' faster arithmetic (Φ from the mass solve's
  // half-way point, a left-looking pivoted Cholesky, Φ⁻¹ from its triangular factor; the same method)
  // draws 15 at the defaults: 03_01 and 12_03 fall. The same 16 runs: 14-17, mean 15.81 before (session
  // 32's figures exactly), 14-17, mean 15.75 after.
  // 2026-11-29 (session 41): the floor no longer pulls within the implicit step (ground_contact.h): 16 up in
  // this test (03_01 up; 12_03 falls), the CLI's 16 likewise; over the 8 settings 15-17, mean 15.25 -> 15.88.
  // 2026-11-29 (session 44): the pelvis's position rows left to the balance level and feet at heel-off held
  // by their toe: 18 up in this test (03_03, 03_04 and 09_12 fall); 16 rounding-level runs 16.81 on average.
  // 2026-11-29 (session 47): the swinging feet's level (the heading through the swing, the horizontal
  // position over its last 30 %; the walks' p95 landing turn 15.2 -> 7.0 deg median over 32 runs) draws 16
  // here: 03_01 and 08_07 fall at their take's end as well. The ensembles rose: 16 runs 16.81 -> 17.12
  // (standard error 0.18), 32 runs 16.78 -> 17.12 (0.15 each); falls per 100 steps 3.41 -> 2.84.
  // 2026-11-30 (session 50): the swing's lift spans the reference's airborne stretch, not the labelled swing (a
  // foot pivoting on the floor labelled lifted stays down): 18 up here (03_01 and 08_07 up again); two 32-run
  // ensembles 17.12 -> 17.62 and 16.84 -> 17.50 (standard errors 0.09-0.15), falls per 100 steps 2.88 -> 2.57.
  // Then the plan's support on the soles' centre lines in turns past 30 deg: 18 here, 17.62 over 32 runs,
  // falls per 100 steps 2.57 -> 2.41 (09_12 falls after 18-21 of its 29 steps instead of 10-19).
  EXPECT_GE(up, 16);
}

}  // namespace
}  // namespace syn
