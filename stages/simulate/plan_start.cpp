#include "stages/simulate/plan_start.h"

#include <algorithm>
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

// The feet's poses and velocities before the shift, and each foot's leg.
struct Feet {
  std::vector<int> links;
  std::vector<Eigen::Isometry3d> poses;
  std::vector<Vector6d> velocities;
  std::vector<LegJoints> legs;
};

// m and rad: a re-solved leg whose foot is this close to its pose keeps it (a swinging foot a centimetre
// off its place is of no consequence; one the leg cannot reach is metres off or turned over).
constexpr double kReachedPosition = 0.02, kReachedAngle = 0.05;
// Halvings of the shift's share tried before starting where the motion starts.
constexpr int kShareHalvings = 8;

// `q`, `u` with the base moved by `share` of the plan's first shift and rate, and each 6-joint leg re-solved
// inside the URDF's limits so its foot keeps its pose and velocity. False if a foot could not keep its pose.
bool ShiftBase(const Model& model, const BalanceShift& plan, const Feet& feet, double share, Workspace& workspace,
               Eigen::Matrix<double, 6, Eigen::Dynamic>& jacobian, Eigen::VectorXd& q, Eigen::VectorXd& u) {
  q[4] += share * plan.position[0].x(), q[5] += share * plan.position[0].y();
  u[3] += share * plan.velocity[0].x(), u[4] += share * plan.velocity[0].y();
  bool reached = true;
  for (int iteration = 0; iteration < 100; ++iteration) {
    workspace.setQ(q);
    reached = true;
    for (size_t f = 0; f < feet.links.size(); ++f) {
      if (feet.legs[f].size() != 6) continue;
      const Eigen::Isometry3d pose = workspace.findLinkPose(feet.links[f]);
      const Eigen::AngleAxisd turn(feet.poses[f].linear() * pose.linear().transpose());
      Vector6d error;
      error.head<3>() = turn.angle() * turn.axis();
      error.tail<3>() = feet.poses[f].translation() - pose.translation();
      reached = reached && error.tail<3>().norm() < kReachedPosition && turn.angle() < kReachedAngle;
      workspace.calcFrameJacobian(feet.links[f], Eigen::Vector3d::Zero(), jacobian);
      Vector6d step = DampedSolve(LegColumns(jacobian, feet.legs[f]), error);
      if (step.cwiseAbs().maxCoeff() > 0.1) step *= 0.1 / step.cwiseAbs().maxCoeff();  // at most 0.1 rad a step
      for (int c = 0; c < 6; ++c) {
        const int index = feet.legs[f][static_cast<size_t>(c)]->q_index;
        q[index] = std::clamp(q[index] + step[c], model.qLower()[index], model.qUpper()[index]);
      }
    }
  }
  if (!reached) return false;
  workspace.setQ(q);
  for (size_t f = 0; f < feet.links.size(); ++f) {
    if (feet.legs[f].size() != 6) continue;
    workspace.calcFrameJacobian(feet.links[f], Eigen::Vector3d::Zero(), jacobian);
    for (const ModelJoint* joint : feet.legs[f]) u[joint->u_index] = 0;
    // The leg's velocities that give the foot its old velocity on top of what the rest of the body gives it.
    const Vector6d leg_velocity = DampedSolve(LegColumns(jacobian, feet.legs[f]), feet.velocities[f] - jacobian * u);
    for (int c = 0; c < 6; ++c) u[feet.legs[f][static_cast<size_t>(c)]->u_index] = leg_velocity[c];
  }
  return true;
}

}  // namespace

void StartOnThePlan(const Model& model, const RobotMap& map, const BalanceShift& plan, Workspace& workspace,
                    Eigen::VectorXd& q, Eigen::VectorXd& u) {
  Feet feet;
  Eigen::Matrix<double, 6, Eigen::Dynamic> jacobian(6, model.nu());
  workspace.setQ(q);
  for (const RobotFoot& foot : map.feet) {
    feet.links.push_back(model.findLinkIndex(foot.link));
    feet.poses.push_back(workspace.findLinkPose(feet.links.back()));
    workspace.calcFrameJacobian(feet.links.back(), Eigen::Vector3d::Zero(), jacobian);
    feet.velocities.push_back(jacobian * u);
    feet.legs.emplace_back();
    for (const ModelJoint* joint : FootChain(model, foot.link)) {
      if (joint->u_index >= 0) feet.legs.back().push_back(joint);
    }
  }
  // The whole shift if the legs reach it inside their limits, else the largest share of it they do (CMU
  // 08_07 onto G1 starts mid-swing with a plan 36 cm off: its swinging foot kept its pose only with the
  // ankle's roll 22° past its limit, and clamped to the limit the leg turned its foot over).
  for (int halving = 0; halving <= kShareHalvings; ++halving) {
    Eigen::VectorXd shifted_q = q, shifted_u = u;
    if (ShiftBase(model, plan, feet, std::ldexp(1.0, -halving), workspace, jacobian, shifted_q, shifted_u)) {
      q = shifted_q, u = shifted_u;
      return;
    }
  }
}

}  // namespace syn
