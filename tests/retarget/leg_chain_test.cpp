// The leg chains contact enforcement solves: found from the URDF, and solved exactly for a reachable foot
// pose (one made by forward kinematics of other leg joints) with every other joint left alone.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "common/model.h"
#include "common/robot_map.h"
#include "stages/retarget/leg_chain.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

class LegChainTest : public ::testing::Test {
 protected:
  LegChainTest()
      : model_(Model::Load(testing::SourcePath("datasets/robots/unitree_g1/g1_29dof.urdf"))), workspace_(model_) {}

  int Coordinate(const std::string& name) const {
    const auto& names = model_.coordinateNames();
    return static_cast<int>(std::find(names.begin(), names.end(), name) - names.begin());
  }

  Model model_;
  Workspace workspace_;
};

TEST_F(LegChainTest, G1LegIsTheSixJointsFromHipToAnkle) {
  const LegChain chain = FindLegChain(model_, workspace_, "left_ankle_roll_link", "g1.toml");
  ASSERT_EQ(chain.size(), 6u);
  const auto& names = model_.coordinateNames();
  EXPECT_EQ(names[static_cast<size_t>(chain.q_index.front())], "left_ankle_roll_joint");
  EXPECT_EQ(names[static_cast<size_t>(chain.q_index.back())], "left_hip_pitch_joint");
  // The knee is a branch joint: its lower limit (−0.087 rad in the URDF) is raised to 0.
  const size_t knee = static_cast<size_t>(std::find(chain.q_index.begin(), chain.q_index.end(), Coordinate("left_knee_joint")) -
                                          chain.q_index.begin());
  ASSERT_LT(knee, chain.size());
  EXPECT_TRUE(chain.branch[knee]);
  EXPECT_EQ(chain.lower[knee], 0.0);
  EXPECT_GT(chain.length, 0.5);
  EXPECT_LT(chain.length, 0.7);
}

TEST_F(LegChainTest, ReachableFootPoseIsSolvedExactlyAndNothingElseMoves) {
  std::vector<LegChain> chains = {FindLegChain(model_, workspace_, "left_ankle_roll_link", "g1.toml"),
                                  FindLegChain(model_, workspace_, "right_ankle_roll_link", "g1.toml")};
  Eigen::VectorXd goal = model_.defaultQ();
  goal.head<4>() = Eigen::Vector4d(std::cos(0.2), 0.0, 0.0, std::sin(0.2));  // base yawed 0.4 rad
  goal.segment<3>(4) = Eigen::Vector3d(0.3, -0.2, 0.7);
  goal[Coordinate("left_hip_pitch_joint")] = -0.6, goal[Coordinate("left_knee_joint")] = 0.9;
  goal[Coordinate("left_ankle_pitch_joint")] = -0.2, goal[Coordinate("left_hip_roll_joint")] = 0.15;
  goal[Coordinate("right_hip_pitch_joint")] = 0.2, goal[Coordinate("right_knee_joint")] = 0.4;
  goal[Coordinate("right_hip_yaw_joint")] = -0.3, goal[Coordinate("right_ankle_roll_joint")] = 0.1;
  goal[Coordinate("waist_yaw_joint")] = 0.3;
  workspace_.setQ(goal);
  std::vector<Eigen::Isometry3d> targets = {workspace_.findLinkPose(chains[0].foot_link), workspace_.findLinkPose(chains[1].foot_link)};
  // Start: the same base and upper body, legs straight.
  Eigen::VectorXd q = goal;
  for (const LegChain& chain : chains) {
    for (int index : chain.q_index) q[index] = 0.0;
  }
  LegSolver solver(model_, chains);
  const LegSolveResult result = solver.solve(targets, {true, true}, q);
  EXPECT_LT(result.position_error, 1e-6);
  EXPECT_LT(result.angle_error, 1e-6);
  EXPECT_LT(result.iterations, 15);
  for (int i = 0; i < model_.nq(); ++i) EXPECT_NEAR(q[i], goal[i], 1e-5) << model_.coordinateNames()[static_cast<size_t>(i)];
}

// The solver's own chain FK (URDF joint frames) against Simbody's, where the leg ends after a solve that
// cannot reach its target, and each joint kept within its velocity limit of the previous frame.
TEST_F(LegChainTest, ReachedPoseIsSimbodysAndTheVelocityBoxHolds) {
  std::vector<LegChain> chains = {FindLegChain(model_, workspace_, "left_ankle_roll_link", "g1.toml")};
  Eigen::VectorXd previous = model_.defaultQ();
  previous.segment<3>(4) = Eigen::Vector3d(0.1, 0.2, 0.75);
  previous[Coordinate("left_knee_joint")] = 0.4, previous[Coordinate("left_hip_pitch_joint")] = -0.3;
  workspace_.setQ(previous);
  Eigen::Isometry3d far = workspace_.findLinkPose(chains[0].foot_link);
  far.translation() += Eigen::Vector3d(0.3, 0.1, 0.2);  // a big step in one frame
  Eigen::VectorXd q = previous;
  LegSolver solver(model_, chains);
  const double dt = 1.0 / 120.0;
  solver.solve({far}, {true}, q, 0.0, &previous, dt);
  for (size_t k = 0; k < chains[0].size(); ++k) {
    const int index = chains[0].q_index[k];
    EXPECT_LE(std::abs(q[index] - previous[index]), chains[0].speed_limit[k] * dt + 1e-12) << model_.coordinateNames()[static_cast<size_t>(index)];
  }
  workspace_.setQ(q);
  const Eigen::Isometry3d simbody = workspace_.findLinkPose(chains[0].foot_link);
  EXPECT_LT((solver.reached(0).translation() - simbody.translation()).norm(), 1e-12);
  EXPECT_LT((solver.reached(0).linear() - simbody.linear()).norm(), 1e-12);
  // Without the box the same step is reached.
  Eigen::VectorXd free = previous;
  const LegSolveResult unbounded = solver.solve({far}, {true}, free);
  EXPECT_LT(unbounded.position_error, 1e-6);
  // A chain marked unbounded (a planted foot's leg, contact_enforcement.h) reaches it with the box given.
  Eigen::VectorXd planted = previous;
  const std::vector<bool> lifted = {true};
  const LegSolveResult over_speed = solver.solve({far}, {true}, planted, 0.0, &previous, dt, &lifted);
  EXPECT_LT(over_speed.position_error, 1e-6);
  EXPECT_LT((planted - free).norm(), 1e-9);
}

// freeJacobian, which the pelvis searches take their Levenberg-Marquardt Jacobian from: at the answer of a
// solve that cannot reach its target, each column is the foot's pose derivative in that joint (central
// differences of Simbody's foot pose; rows angle_scale × angular velocity, then linear), and the columns of
// the joints the solve left on a bound (the velocity box's or a position limit) are zero.
TEST_F(LegChainTest, FreeJacobianIsTheFootsDerivativeInTheJointsOffTheirBounds) {
  std::vector<LegChain> chains = {FindLegChain(model_, workspace_, "left_ankle_roll_link", "g1.toml")};
  const LegChain& chain = chains[0];
  Eigen::VectorXd previous = model_.defaultQ();
  previous.segment<3>(4) = Eigen::Vector3d(0.1, 0.2, 0.75);
  previous[Coordinate("left_knee_joint")] = 0.4, previous[Coordinate("left_hip_pitch_joint")] = -0.3;
  workspace_.setQ(previous);
  Eigen::Isometry3d far = workspace_.findLinkPose(chain.foot_link);
  far.translation() += Eigen::Vector3d(0.3, 0.1, 0.2);
  Eigen::VectorXd q = previous;
  LegSolver solver(model_, chains);
  const double dt = 1.0 / 120.0;
  solver.solve({far}, {true}, q, 0.0, &previous, dt);
  const LegSolver::ChainJacobian& jacobian = solver.freeJacobian(0);
  ASSERT_EQ(jacobian.cols(), static_cast<Eigen::Index>(chain.size()));
  int on_bound = 0, free = 0;
  constexpr double h = 1e-6;
  for (size_t k = 0; k < chain.size(); ++k) {
    const int index = chain.q_index[k];
    const std::string& name = model_.coordinateNames()[static_cast<size_t>(index)];
    const double reach = chain.speed_limit[k] * dt;
    const double lower = std::max(chain.lower[k], previous[index] - reach), upper = std::min(chain.upper[k], previous[index] + reach);
    if (q[index] <= lower + 1e-12 || q[index] >= upper - 1e-12) {
      ++on_bound;
      EXPECT_EQ(jacobian.col(static_cast<Eigen::Index>(k)).norm(), 0.0) << name << " is on a bound";
      continue;
    }
    ++free;
    Eigen::VectorXd plus = q, minus = q;
    plus[index] += h, minus[index] -= h;
    workspace_.setQ(plus);
    const Eigen::Isometry3d after = workspace_.findLinkPose(chain.foot_link);
    workspace_.setQ(minus);
    const Eigen::Isometry3d before = workspace_.findLinkPose(chain.foot_link);
    const Eigen::AngleAxisd turn(after.linear() * before.linear().transpose());
    Eigen::Matrix<double, 6, 1> expected;
    expected << solver.angleScale() * turn.axis() * turn.angle() / (2 * h), (after.translation() - before.translation()) / (2 * h);
    EXPECT_LT((jacobian.col(static_cast<Eigen::Index>(k)) - expected).norm(), 1e-7) << name;
  }
  // The big step leaves some joints on their velocity box and some free, so both kinds are checked.
  EXPECT_GT(on_bound, 0);
  EXPECT_GT(free, 0);
}

// HRP-4C: a virtual floating base (six massless joints) above the legs, and its own joint frames.
TEST(LegChainHrp4c, ReachedPoseIsSimbodys) {
  SYN_REQUIRE_SHARED("robots/humanoid_synergies/HRP4c_optitrack_model.urdf");
  const Model model = Model::Load(testing::SharedPath("robots/humanoid_synergies/HRP4c_optitrack_model.urdf"));
  Workspace workspace(model);
  const RobotMap map = LoadRobotMap(testing::SourcePath("manifests/robots/hrp4c.toml"));
  std::vector<LegChain> chains;
  for (const RobotFoot& foot : map.feet) chains.push_back(FindLegChain(model, workspace, foot.link, "hrp4c.toml"));
  ASSERT_EQ(chains.size(), 2u);
  Eigen::VectorXd q = model.defaultQ();
  for (int i = 0; i < model.nq(); ++i) q[i] = 0.1 * std::sin(1.7 * i + 0.3);  // every joint off zero, base too
  workspace.setQ(q);
  std::vector<Eigen::Isometry3d> targets;
  for (const LegChain& chain : chains) {
    Eigen::Isometry3d target = workspace.findLinkPose(chain.foot_link);
    target.translation().z() += 0.05;
    targets.push_back(target);
  }
  LegSolver solver(model, chains);
  solver.solve(targets, {true, true}, q);
  workspace.setQ(q);
  for (size_t c = 0; c < chains.size(); ++c) {
    const Eigen::Isometry3d simbody = workspace.findLinkPose(chains[c].foot_link);
    EXPECT_LT((solver.reached(c).translation() - simbody.translation()).norm(), 1e-12);
    EXPECT_LT((solver.reached(c).linear() - simbody.linear()).norm(), 1e-12);
    EXPECT_LT((simbody.translation() - targets[c].translation()).norm(), 1e-5);  // a 5 cm lift is reachable
  }
}

TEST_F(LegChainTest, InactiveChainIsLeftAlone) {
  std::vector<LegChain> chains = {FindLegChain(model_, workspace_, "left_ankle_roll_link", "g1.toml")};
  Eigen::VectorXd q = model_.defaultQ();
  q[Coordinate("left_knee_joint")] = 0.5;
  const Eigen::VectorXd before = q;
  LegSolver solver(model_, chains);
  solver.solve({Eigen::Isometry3d::Identity()}, {false}, q);
  EXPECT_EQ(q, before);
}

}  // namespace
}  // namespace syn
