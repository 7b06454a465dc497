#include "stages/simulate/plan_start.h"

#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

namespace syn {
namespace {

using LegJoints = std::vector<const ModelJoint*>;

// The leg's columns of a foot's frame Jacobian.
Eigen::Matrix<double, 6, 6> LegColumns(const Eigen::Matrix<double, 6, Eigen::Dynamic>& jacobian, const LegJoints& leg) {
  Eigen::Matrix<double, 6, 6> columns;
  for (int c = 0; c < 6; ++c) columns.col(c) = jacobian.col(leg[static_cast<size_t>(c)]->u_index);
  return columns;
}

// Damped least squares: the joint change that moves the foot by `wanted`, bounded where the leg is singular
// (a straight knee).
Vector6d DampedSolve(const Eigen::Matrix<double, 6, 6>& columns, const Vector6d& wanted) {
  const Eigen::Matrix<double, 6, 6> normal = columns.transpose() * columns + 1e-4 * Eigen::Matrix<double, 6, 6>::Identity();
  return normal.ldlt().solve(columns.transpose() * wanted);
}

}  // namespace

void StartOnThePlan(const Model& model, const RobotMap& map, const BalanceShift& plan, Workspace& workspace,
                    Eigen::VectorXd& q, Eigen::VectorXd& u) {
  const int nu = model.nu();
  std::vector<int> feet;
  std::vector<Eigen::Isometry3d> poses;
  std::vector<Vector6d> velocities;
  Eigen::Matrix<double, 6, Eigen::Dynamic> jacobian(6, nu);
  workspace.setQ(q);
  for (const RobotFoot& foot : map.feet) {
    feet.push_back(model.findLinkIndex(foot.link));
    poses.push_back(workspace.findLinkPose(feet.back()));
    workspace.calcFrameJacobian(feet.back(), Eigen::Vector3d::Zero(), jacobian);
    velocities.push_back(jacobian * u);
  }
  // Each foot's leg: the moving joints on that foot's chain.
  std::vector<LegJoints> legs(feet.size());
  for (size_t f = 0; f < feet.size(); ++f) {
    for (const ModelJoint* joint : FootChain(model, map.feet[f].link)) {
      if (joint->u_index >= 0) legs[f].push_back(joint);
    }
  }
  q[4] += plan.position[0].x(), q[5] += plan.position[0].y();
  u[3] += plan.velocity[0].x(), u[4] += plan.velocity[0].y();
  for (int iteration = 0; iteration < 100; ++iteration) {
    workspace.setQ(q);
    for (size_t f = 0; f < feet.size(); ++f) {
      if (legs[f].size() != 6) continue;
      const Eigen::Isometry3d pose = workspace.findLinkPose(feet[f]);
      const Eigen::AngleAxisd turn(poses[f].linear() * pose.linear().transpose());
      Vector6d error;
      error.head<3>() = turn.angle() * turn.axis();
      error.tail<3>() = poses[f].translation() - pose.translation();
      workspace.calcFrameJacobian(feet[f], Eigen::Vector3d::Zero(), jacobian);
      Vector6d step = DampedSolve(LegColumns(jacobian, legs[f]), error);
      if (step.cwiseAbs().maxCoeff() > 0.1) step *= 0.1 / step.cwiseAbs().maxCoeff();  // at most 0.1 rad a step
      for (int c = 0; c < 6; ++c) q[legs[f][static_cast<size_t>(c)]->q_index] += step[c];
    }
  }
  workspace.setQ(q);
  for (size_t f = 0; f < feet.size(); ++f) {
    if (legs[f].size() != 6) continue;
    workspace.calcFrameJacobian(feet[f], Eigen::Vector3d::Zero(), jacobian);
    for (const ModelJoint* joint : legs[f]) u[joint->u_index] = 0;
    // The leg's velocities that give the foot its old velocity on top of what the rest of the body gives it.
    const Vector6d leg_velocity = DampedSolve(LegColumns(jacobian, legs[f]), velocities[f] - jacobian * u);
    for (int c = 0; c < 6; ++c) u[legs[f][static_cast<size_t>(c)]->u_index] = leg_velocity[c];
  }
}

}  // namespace syn
