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
    // The toe: the sole points furthest forward (within 0.1 mm), averaged (G1: the two front spheres).
    double front = -std::numeric_limits<double>::infinity();
    for (const Eigen::Vector3d& point : sole_points_.back()) front = std::max(front, point.x());
    Eigen::Vector3d toe = Eigen::Vector3d::Zero();
    int toe_points = 0;
    for (const Eigen::Vector3d& point : sole_points_.back()) {
      if (point.x() >= front - 1e-4) toe += point, ++toe_points;
    }
    toe_.push_back(toe_points > 0 ? Eigen::Vector3d(toe / toe_points) : sole_centre_.back());
  }
  pose_.resize(feet.size());
  foot_jacobian_.resize(6, model.nu());
}

int StanceFeet::update(Workspace& workspace, const int64_t* planted, const double* reference_heading, const char* heel_off) {
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
    const bool by_the_toe = hold && heel_off != nullptr && heel_off[f] != 0;
    if (by_the_toe && !stance.heel_off) {
      stance.toe_anchor = pose * toe_[f];
      stance.toe_anchor.z() = 0.0;
    }
    stance.heel_off = by_the_toe;
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
  Eigen::Index rows = 0;
  for (const Stance& stance : stance_) rows += !stance.held ? 0 : stance.heel_off ? 4 : 6;
  if (jacobian_.rows() != rows) {
    jacobian_.resize(rows, nu);
    acceleration_.resize(rows);
  }
  const Eigen::VectorXd& u = workspace.getU();
  const double kp = options_.stiffness, kv = 2.0 * std::sqrt(options_.stiffness);
  Eigen::Index row = 0;
  for (size_t f = 0; f < stance_.size(); ++f) {
    if (!stance_[f].held) continue;
    const Eigen::Isometry3d& pose = pose_[f];
    // Counted as held, and as tilted when it is (a heel-off hold is, by design): the same measure the
    // recorded frames give.
    ++held_foot_steps_;
    if (SoleTilt(pose.linear()) > options_.off_flat) ++tilted_foot_steps_;
    if (stance_[f].heel_off) {
      workspace.calcFrameJacobian(foot_links_[f], toe_[f], foot_jacobian_);
      const Eigen::Matrix<double, 6, 1> velocity = foot_jacobian_ * u;
      const Eigen::Matrix<double, 6, 1> bias = workspace.calcFrameBiasAcceleration(foot_links_[f], toe_[f]);
      const double heading_error = std::remainder(stance_[f].yaw - Heading(pose.linear()), 2 * M_PI);
      jacobian_.row(row) = foot_jacobian_.row(2);
      acceleration_[row] = kp * heading_error - kv * velocity[2] - bias[2];
      jacobian_.middleRows(row + 1, 3) = foot_jacobian_.bottomRows<3>();
      acceleration_.segment(row + 1, 3) = kp * (stance_[f].toe_anchor - pose * toe_[f]) - kv * velocity.tail<3>() - bias.tail<3>();
      row += 4;
      continue;
    }
    workspace.calcFrameJacobian(foot_links_[f], sole_centre_[f], foot_jacobian_);
    const Eigen::Matrix<double, 6, 1> velocity = foot_jacobian_ * u;
    const Eigen::Matrix<double, 6, 1> bias = workspace.calcFrameBiasAcceleration(foot_links_[f], sole_centre_[f]);
    // Flat: the sole's plane is the foot link's x-y plane (the robot maps' sole points share their z).
    const Eigen::Matrix3d wanted = Eigen::AngleAxisd(stance_[f].yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    const Eigen::AngleAxisd turn(wanted * pose.linear().transpose());
    Eigen::Matrix<double, 6, 1> error;
    error.head<3>() = turn.angle() * turn.axis();
    error.tail<3>() = stance_[f].anchor - pose * sole_centre_[f];
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
