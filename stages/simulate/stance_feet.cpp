#include "stages/simulate/stance_feet.h"

#include <cmath>
#include <limits>

#include <Eigen/Geometry>

namespace syn {

StanceFeet::StanceFeet(const Model& model, const std::vector<RobotFoot>& feet, const StanceFeetOptions& options)
    : options_(options), stance_(feet.size()) {
  for (const RobotFoot& foot : feet) {
    foot_links_.push_back(model.findLinkIndex(foot.link));
    sole_points_.emplace_back();
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (const std::array<double, 3>& p : foot.sole_points) {
      sole_points_.back().emplace_back(p[0], p[1], p[2]);
      centre += sole_points_.back().back();
    }
    sole_centre_.push_back(foot.sole_points.empty() ? centre : Eigen::Vector3d(centre / static_cast<double>(foot.sole_points.size())));
  }
  pose_.resize(feet.size());
  foot_jacobian_.resize(6, model.nu());
}

int StanceFeet::update(Workspace& workspace, const int64_t* planted) {
  int held = 0;
  for (size_t f = 0; f < stance_.size(); ++f) {
    const Eigen::Isometry3d& pose = pose_[f] = workspace.findLinkPose(foot_links_[f]);
    double lowest = std::numeric_limits<double>::infinity();
    for (const Eigen::Vector3d& point : sole_points_[f]) lowest = std::min(lowest, (pose * point).z());
    const bool hold = planted[f] != 0 && lowest <= options_.touch_height;
    if (hold && !stance_[f].held) {
      stance_[f].anchor = pose * sole_centre_[f];
      stance_[f].anchor.z() = 0.0;
      stance_[f].yaw = std::atan2(pose.linear()(1, 0), pose.linear()(0, 0));
    }
    stance_[f].held = hold;
    held += hold ? 1 : 0;
  }
  const Eigen::Index nu = foot_jacobian_.cols();
  if (jacobian_.rows() != 6 * held) {
    jacobian_.resize(6 * held, nu);
    acceleration_.resize(6 * held);
  }
  const Eigen::VectorXd& u = workspace.getU();
  const double kp = options_.stiffness, kv = 2.0 * std::sqrt(options_.stiffness);
  Eigen::Index row = 0;
  for (size_t f = 0; f < stance_.size(); ++f) {
    if (!stance_[f].held) continue;
    const Eigen::Isometry3d& pose = pose_[f];
    workspace.calcFrameJacobian(foot_links_[f], sole_centre_[f], foot_jacobian_);
    const Eigen::Matrix<double, 6, 1> velocity = foot_jacobian_ * u;
    const Eigen::Matrix<double, 6, 1> bias = workspace.calcFrameBiasAcceleration(foot_links_[f], sole_centre_[f]);
    // Flat: the sole's plane is the foot link's x-y plane (the robot maps' sole points share their z).
    const Eigen::Matrix3d wanted = Eigen::AngleAxisd(stance_[f].yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    const Eigen::AngleAxisd turn(wanted * pose.linear().transpose());
    Eigen::Matrix<double, 6, 1> error;
    error.head<3>() = turn.angle() * turn.axis();
    error.tail<3>() = stance_[f].anchor - pose * sole_centre_[f];
    ++held_foot_steps_;
    if (std::hypot(error[0], error[1]) > options_.off_flat) ++tilted_foot_steps_;
    jacobian_.middleRows(row, 6) = foot_jacobian_;
    acceleration_.segment(row, 6) = kp * error - kv * velocity - bias;
    row += 6;
  }
  return held;
}

}  // namespace syn
