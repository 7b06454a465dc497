#include "stages/simulate/stance_feet.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <Eigen/Geometry>

#include "common/percentile.h"

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

int StanceFeet::update(Workspace& workspace, const int64_t* planted, const double* reference_heading) {
  int held = 0;
  for (size_t f = 0; f < stance_.size(); ++f) {
    const Eigen::Isometry3d& pose = pose_[f] = workspace.findLinkPose(foot_links_[f]);
    double lowest = std::numeric_limits<double>::infinity();
    for (const Eigen::Vector3d& point : sole_points_[f]) lowest = std::min(lowest, (pose * point).z());
    const bool hold = planted[f] != 0 && lowest <= options_.touch_height;
    Stance& stance = stance_[f];
    const Eigen::Vector3d centre = pose * sole_centre_[f];
    const double yaw = Heading(pose.linear());
    if (hold && !stance.held) {
      stance.anchor = centre;
      stance.anchor.z() = 0.0;
      stance.yaw = yaw;
    }
    stance.held = hold;
    // The source's phase: it ends when the source lifts the foot.
    if (planted[f] == 0) {
      if (stance.phase_held) phase_turns_.push_back(stance.phase_turn), phase_moves_.push_back(stance.phase_move);
      stance.phase_held = false;
    }
    if (hold && !stance.phase_held) {
      stance.phase_held = true;
      stance.phase_start = centre.head<2>();
      stance.phase_yaw = yaw;
      stance.phase_turn = stance.phase_move = 0.0;
      if (reference_heading != nullptr && std::isfinite(reference_heading[f])) {
        landing_turns_.push_back(std::abs(std::remainder(yaw - reference_heading[f], 2 * M_PI)));
      }
    }
    if (stance.phase_held) {
      stance.phase_turn = std::max(stance.phase_turn, std::abs(std::remainder(yaw - stance.phase_yaw, 2 * M_PI)));
      stance.phase_move = std::max(stance.phase_move, (centre.head<2>() - stance.phase_start).norm());
    }
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

void StanceFeet::reservePhases(size_t phases) {
  phase_turns_.reserve(phases);
  phase_moves_.reserve(phases);
  landing_turns_.reserve(phases);
}

StanceFeet::PhaseDrift StanceFeet::phaseDrift() const {
  std::vector<double> turns = phase_turns_, moves = phase_moves_;  // after the run: allocating is fine
  for (const Stance& stance : stance_) {
    if (stance.phase_held) turns.push_back(stance.phase_turn), moves.push_back(stance.phase_move);
  }
  PhaseDrift drift;
  drift.landings = static_cast<int64_t>(landing_turns_.size());
  if (!landing_turns_.empty()) {
    const Spread landing = MedianP95Largest(landing_turns_);
    drift.median_landing_turn = landing.median, drift.p95_landing_turn = landing.p95, drift.largest_landing_turn = landing.largest;
  }
  drift.phases = static_cast<int64_t>(turns.size());
  if (turns.empty()) return drift;
  const Spread turn = MedianP95Largest(turns), move = MedianP95Largest(moves);
  drift.median_turn = turn.median, drift.p95_turn = turn.p95, drift.largest_turn = turn.largest;
  drift.median_move = move.median, drift.p95_move = move.p95, drift.largest_move = move.largest;
  return drift;
}

}  // namespace syn
