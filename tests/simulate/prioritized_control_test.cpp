// The task hierarchy against a dense reference computation, and strict priority: a priority-2 task
// that conflicts with priority 1 leaves priority 1 exactly as it was.
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <random>

#include <Eigen/Dense>
#include <gtest/gtest.h>

#include "common/model.h"
#include "stages/simulate/prioritized_control.h"
#include "tests/support/scratch_file.h"

namespace syn {
namespace {

// A small free-floating robot: a 2 kg torso with a 4-joint arm and a 2-joint arm (nu = 6 + 6).
Model SmallRobotModel() {
  const testing::ScratchFile urdf("small_robot", ".urdf", R"(<robot name="small">
  <link name="torso"><inertial><mass value="2"/><inertia ixx="0.05" iyy="0.04" izz="0.03" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="a1"><inertial><origin xyz="0.1 0 0"/><mass value="0.8"/><inertia ixx="0.002" iyy="0.006" izz="0.006" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="a2"><inertial><origin xyz="0.1 0 0"/><mass value="0.6"/><inertia ixx="0.002" iyy="0.005" izz="0.005" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="a3"><inertial><origin xyz="0.1 0 0"/><mass value="0.5"/><inertia ixx="0.001" iyy="0.004" izz="0.004" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="a4"><inertial><origin xyz="0.05 0 0"/><mass value="0.3"/><inertia ixx="0.001" iyy="0.002" izz="0.002" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="b1"><inertial><origin xyz="0 0.1 0"/><mass value="0.7"/><inertia ixx="0.005" iyy="0.002" izz="0.005" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="b2"><inertial><origin xyz="0 0.1 0"/><mass value="0.4"/><inertia ixx="0.003" iyy="0.001" izz="0.003" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="ja1" type="revolute"><parent link="torso"/><child link="a1"/><origin xyz="0.1 0 0.1"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="0" velocity="0"/></joint>
  <joint name="ja2" type="revolute"><parent link="a1"/><child link="a2"/><origin xyz="0.2 0 0"/><axis xyz="0 1 0"/><limit lower="-3" upper="3" effort="0" velocity="0"/></joint>
  <joint name="ja3" type="revolute"><parent link="a2"/><child link="a3"/><origin xyz="0.2 0 0"/><axis xyz="1 0 0"/><limit lower="-3" upper="3" effort="0" velocity="0"/></joint>
  <joint name="ja4" type="revolute"><parent link="a3"/><child link="a4"/><origin xyz="0.2 0 0"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="0" velocity="0"/></joint>
  <joint name="jb1" type="revolute"><parent link="torso"/><child link="b1"/><origin xyz="0 0.1 -0.1"/><axis xyz="1 0 0"/><limit lower="-3" upper="3" effort="0" velocity="0"/></joint>
  <joint name="jb2" type="revolute"><parent link="b1"/><child link="b2"/><origin xyz="0 0.2 0"/><axis xyz="0 0 1"/><limit lower="-3" upper="3" effort="0" velocity="0"/></joint>
</robot>)");
  return Model::Load(urdf.path());
}

struct SmallRobot {
  Model model;
  Workspace workspace;
  TreeMassFactorization mass;
  explicit SmallRobot(uint32_t seed) : model(SmallRobotModel()), workspace(model), mass(model) {
    std::mt19937 random(seed);
    std::uniform_real_distribution<double> uniform(-1.0, 1.0);
    Eigen::VectorXd q(model.nq()), u(model.nu());
    for (int i = 0; i < q.size(); ++i) q[i] = uniform(random);
    for (int i = 0; i < u.size(); ++i) u[i] = uniform(random);
    workspace.setQ(q);
    workspace.setU(u);
    mass.factor(workspace);
  }
  Eigen::Matrix<double, 6, Eigen::Dynamic> jacobian(const std::string& link) {
    Eigen::Matrix<double, 6, Eigen::Dynamic> j;
    workspace.calcFrameJacobian(model.findLinkIndex(link), Eigen::Vector3d::Zero(), j);
    return j;
  }
  // A formed column by column from the O(n) operator: for the reference only.
  Eigen::MatrixXd massMatrix() {
    const int n = model.nu();
    Eigen::MatrixXd a(n, n);
    Eigen::VectorXd column(n);
    for (int i = 0; i < n; ++i) {
      workspace.calcMassTimes(Eigen::VectorXd::Unit(n, i), column);
      a.col(i) = column;
    }
    return a;
  }
};

// Level 1: the 4-joint arm's tip pose (6 rows). Level 2: the torso orientation and the other arm's tip
// height (4 rows), within the 6 velocities level 1 leaves free.
std::vector<PriorityLevel> Levels(SmallRobot& robot, bool with_level_2) {
  std::vector<PriorityLevel> levels(with_level_2 ? 2 : 1);
  levels[0].jacobian = robot.jacobian("a4");
  levels[0].acceleration = (Eigen::VectorXd(6) << 0.3, -0.2, 0.5, 1.0, -2.0, 0.7).finished();
  if (with_level_2) {
    levels[1].jacobian.resize(4, robot.model.nu());
    levels[1].jacobian.topRows(3) = robot.jacobian("torso").topRows(3);
    levels[1].jacobian.bottomRows(1) = robot.jacobian("b2").bottomRows(1);
    levels[1].acceleration = (Eigen::VectorXd(4) << 4.0, -3.0, 2.0, 1.5).finished();
  }
  return levels;
}

TEST(PrioritizedControl, MatchesDenseReferenceComputation) {
  SmallRobot robot(7);
  const int n = robot.model.nu();
  const std::vector<PriorityLevel> levels = Levels(robot, true);
  Eigen::VectorXd posture = Eigen::VectorXd::LinSpaced(n, -1.0, 2.0);
  PrioritizedControlOptions undamped;  // the textbook law the dense reference computes
  undamped.damping = 0.0;
  PrioritizedControl control(undamped);
  Eigen::VectorXd torques;
  control.calcTorques(robot.workspace, robot.mass, levels, posture, torques);
  ASSERT_EQ(control.keptRank(0), 6);
  ASSERT_EQ(control.keptRank(1), 4);

  // Dense: A, A⁻¹, and the textbook recursion with explicit projectors.
  const Eigen::MatrixXd a = robot.massMatrix();
  const Eigen::MatrixXd a_inv = a.inverse();
  Eigen::MatrixXd null_space = Eigen::MatrixXd::Identity(n, n);
  Eigen::VectorXd reference = Eigen::VectorXd::Zero(n);
  for (const PriorityLevel& level : levels) {
    const Eigen::MatrixXd projected = level.jacobian * null_space;
    const Eigen::MatrixXd inertia = (projected * a_inv * projected.transpose()).inverse();
    const Eigen::VectorXd force = inertia * (level.acceleration - level.jacobian * a_inv * reference);
    reference += projected.transpose() * force;
    const Eigen::MatrixXd consistent_inverse = a_inv * projected.transpose() * inertia;
    null_space = null_space * (Eigen::MatrixXd::Identity(n, n) - consistent_inverse * projected);
  }
  reference += null_space.transpose() * a * posture;
  EXPECT_LT((torques - reference).norm(), 1e-8 * reference.norm()) << torques.transpose() << "\n" << reference.transpose();

  // Dynamic consistency: the level-2 and posture torques give level 1 no acceleration, so level 1 gets
  // exactly what it asked; level 2 gets what it asked within what level 1 leaves free.
  const Eigen::VectorXd udot = a_inv * torques;
  EXPECT_LT((levels[0].jacobian * udot - levels[0].acceleration).norm(), 1e-9);
  EXPECT_LT((control.taskAcceleration() - a_inv * (torques - null_space.transpose() * a * posture)).norm(), 1e-9);
  const Eigen::MatrixXd level1_null = Eigen::MatrixXd::Identity(n, n) -
      a_inv * levels[0].jacobian.transpose() *
          (levels[0].jacobian * a_inv * levels[0].jacobian.transpose()).inverse() * levels[0].jacobian;
  EXPECT_LT((levels[0].jacobian * a_inv * level1_null.transpose()).norm(), 1e-9);
}

TEST(PrioritizedControl, ConflictingPriority2LeavesPriority1Unchanged) {
  SmallRobot robot(11);
  const int n = robot.model.nu();
  const Eigen::VectorXd posture = Eigen::VectorXd::Constant(n, 0.5);
  PrioritizedControl alone, stacked;
  Eigen::VectorXd torques_alone, torques_stacked, udot_alone, udot_stacked;
  alone.calcTorques(robot.workspace, robot.mass, Levels(robot, false), posture, torques_alone);
  // Level 2 asks for more than the 6 velocities level 1 leaves free, including the level-1 link's own
  // position with another acceleration: torso orientation, the arm's elbow and tip positions.
  std::vector<PriorityLevel> levels = Levels(robot, false);
  levels.emplace_back();
  levels[1].jacobian.resize(9, n);
  levels[1].jacobian.topRows(3) = robot.jacobian("torso").topRows(3);
  levels[1].jacobian.middleRows(3, 3) = robot.jacobian("a3").bottomRows(3);
  levels[1].jacobian.bottomRows(3) = robot.jacobian("a4").bottomRows(3);
  levels[1].acceleration = (Eigen::VectorXd(9) << 4.0, -3.0, 2.0, -5.0, 6.0, 1.5, -1.0, 2.0, -3.0).finished();
  stacked.calcTorques(robot.workspace, robot.mass, levels, posture, torques_stacked);
  robot.workspace.calcMassInverseTimes(torques_alone, udot_alone);
  robot.workspace.calcMassInverseTimes(torques_stacked, udot_stacked);
  const Eigen::VectorXd level1_alone = levels[0].jacobian * udot_alone;
  const Eigen::VectorXd level1_stacked = levels[0].jacobian * udot_stacked;
  EXPECT_LT((level1_alone - level1_stacked).norm(), 1e-9);
  // The default damping (1e-3 on the unit-diagonal task inertia) shortens the force a little.
  EXPECT_LT((level1_stacked - levels[0].acceleration).norm(), 0.01 * levels[0].acceleration.norm());
  // The conflict is real: priority 2 does not get what it asked for, and changes the motion.
  EXPECT_GT((levels[1].jacobian * udot_stacked - levels[1].acceleration).norm(), 0.1);
  EXPECT_GT((udot_alone - udot_stacked).norm(), 0.1);
  EXPECT_LE(stacked.keptRank(1), n - 6);
}

// A level with a nearly dependent row (the tip's x position a second time, 1 mm along the link: its
// mobility is almost all given by the first) keeps no more rows than without it at a cutoff of 0.5,
// and the level below still cannot change what the kept rows get.
TEST(PrioritizedControl, DroppedRowsLeaveTheKeptRowsStrictlyAbove) {
  SmallRobot robot(23);
  const int n = robot.model.nu();
  const Eigen::VectorXd posture = Eigen::VectorXd::Constant(n, -0.3);
  Eigen::Matrix<double, 6, Eigen::Dynamic> offset_point;
  robot.workspace.calcFrameJacobian(robot.model.findLinkIndex("a4"), Eigen::Vector3d(0.001, 0, 0), offset_point);
  std::vector<PriorityLevel> levels = Levels(robot, true);
  PriorityLevel& top = levels[0];
  top.jacobian.conservativeResize(7, n);
  top.jacobian.row(6) = offset_point.row(3);
  top.acceleration.conservativeResize(7);
  top.acceleration[6] = top.acceleration[3] + 0.5;  // a conflict the dropped row loses
  PrioritizedControlOptions options;
  options.independence_cutoff = 0.5;
  PrioritizedControl alone(options), stacked(options);
  Eigen::VectorXd torques_alone, torques_stacked, udot_alone, udot_stacked;
  alone.calcTorques(robot.workspace, robot.mass, {top}, posture, torques_alone);
  stacked.calcTorques(robot.workspace, robot.mass, levels, posture, torques_stacked);
  PrioritizedControl without_twin(options);
  Eigen::VectorXd torques_without_twin;
  without_twin.calcTorques(robot.workspace, robot.mass, Levels(robot, false), posture, torques_without_twin);
  EXPECT_EQ(stacked.keptRank(0), without_twin.keptRank(0));
  ASSERT_GE(stacked.keptRank(0), 4);
  robot.workspace.calcMassInverseTimes(torques_alone, udot_alone);
  robot.workspace.calcMassInverseTimes(torques_stacked, udot_stacked);
  const Eigen::VectorXd change = top.jacobian * (udot_stacked - udot_alone);
  int unchanged = 0;
  for (int r = 0; r < 7; ++r) unchanged += std::abs(change[r]) < 1e-9 ? 1 : 0;
  EXPECT_GE(unchanged, stacked.keptRank(0)) << change.transpose();
  EXPECT_LT(unchanged, 7) << "a dropped row passes to the level below";
  EXPECT_GT((udot_stacked - udot_alone).norm(), 0.1);  // level 2 does act
}

}  // namespace
}  // namespace syn
