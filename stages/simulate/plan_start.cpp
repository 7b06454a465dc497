#include "stages/simulate/plan_start.h"

#include <string>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Geometry>

namespace syn {

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
  // Each foot's leg: the joints whose child link is on that foot's chain.
  std::vector<std::vector<const ModelJoint*>> legs(feet.size());
  for (size_t f = 0; f < feet.size(); ++f) {
    std::string link = map.feet[f].link;
    for (bool found = true; found;) {
      found = false;
      for (const ModelJoint& joint : model.joints()) {
        if (joint.child != link || joint.type == "free") continue;
        if (joint.u_index >= 0) legs[f].push_back(&joint);
        link = joint.parent;
        found = true;
        break;
      }
    }
  }
  q[4] += plan.position[0].x(), q[5] += plan.position[0].y();
  u[3] += plan.velocity[0].x(), u[4] += plan.velocity[0].y();
  for (int iteration = 0; iteration < 100; ++iteration) {
    workspace.setQ(q);
    for (size_t f = 0; f < feet.size(); ++f) {
      if (legs[f].size() != 6) continue;
      const Eigen::Isometry3d pose = workspace.findLinkPose(feet[f]);
      Vector6d error;
      error.head<3>() = Eigen::AngleAxisd(poses[f].linear() * pose.linear().transpose()).angle() *
                        Eigen::AngleAxisd(poses[f].linear() * pose.linear().transpose()).axis();
      error.tail<3>() = poses[f].translation() - pose.translation();
      workspace.calcFrameJacobian(feet[f], Eigen::Vector3d::Zero(), jacobian);
      Eigen::Matrix<double, 6, 6> leg;
      for (int c = 0; c < 6; ++c) leg.col(c) = jacobian.col(legs[f][static_cast<size_t>(c)]->u_index);
      // Damped least squares, each step at most 0.1 rad: a straight knee makes the leg singular.
      const Eigen::Matrix<double, 6, 6> normal = leg.transpose() * leg + 1e-4 * Eigen::Matrix<double, 6, 6>::Identity();
      Vector6d step = normal.ldlt().solve(leg.transpose() * error);
      if (step.cwiseAbs().maxCoeff() > 0.1) step *= 0.1 / step.cwiseAbs().maxCoeff();
      for (int c = 0; c < 6; ++c) q[legs[f][static_cast<size_t>(c)]->q_index] += step[c];
    }
  }
  workspace.setQ(q);
  for (size_t f = 0; f < feet.size(); ++f) {
    if (legs[f].size() != 6) continue;
    workspace.calcFrameJacobian(feet[f], Eigen::Vector3d::Zero(), jacobian);
    Eigen::Matrix<double, 6, 6> leg;
    for (int c = 0; c < 6; ++c) {
      leg.col(c) = jacobian.col(legs[f][static_cast<size_t>(c)]->u_index);
      u[legs[f][static_cast<size_t>(c)]->u_index] = 0;
    }
    const Vector6d rest = velocities[f] - jacobian * u;
    const Eigen::Matrix<double, 6, 6> normal = leg.transpose() * leg + 1e-4 * Eigen::Matrix<double, 6, 6>::Identity();
    const Vector6d leg_velocity = normal.ldlt().solve(leg.transpose() * rest);
    for (int c = 0; c < 6; ++c) u[legs[f][static_cast<size_t>(c)]->u_index] = leg_velocity[c];
  }
}

}  // namespace syn
