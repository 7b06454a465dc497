#include "stages/simulate/operational_space_controller.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace syn {
namespace {

// Rotation vector of r_target · rᵀ (ground frame): the angular error that takes r to r_target.
Eigen::Vector3d OrientationError(const Eigen::Quaterniond& target, const Eigen::Matrix3d& rotation) {
  Eigen::Quaterniond difference = target * Eigen::Quaterniond(rotation).conjugate();
  if (difference.w() < 0) difference.coeffs() = -difference.coeffs();  // the short way round
  const Eigen::AngleAxisd angle_axis(difference);
  return angle_axis.angle() * angle_axis.axis();
}

}  // namespace

OperationalSpaceController::OperationalSpaceController(const Model& model, std::vector<ControlledTask> tasks,
                                                       const ControllerOptions& options)
    : options_(options),
      tasks_(std::move(tasks)),
      hierarchy_(options.hierarchy),
      free_base_(model.hasFreeBase()),
      effort_limit_(model.effortLimit()) {
  const int nu = model.nu();
  // One level per distinct priority, highest (smallest number) first.
  std::map<int, int> level_of_priority;
  for (const ControlledTask& task : tasks_) level_of_priority[task.priority] = 0;
  int next_level = 0;
  for (auto& [priority, level] : level_of_priority) level = next_level++;
  std::vector<Eigen::Index> level_rows(level_of_priority.size(), 0);
  for (size_t i = 0; i < tasks_.size(); ++i) {
    const int level = level_of_priority[tasks_[i].priority];
    rows_.push_back({i, level, level_rows[static_cast<size_t>(level)]});
    level_rows[static_cast<size_t>(level)] += tasks_[i].type == TaskType::kPose ? 6 : 3;
  }
  levels_.resize(level_rows.size());
  for (size_t k = 0; k < levels_.size(); ++k) {
    levels_[k].jacobian = Eigen::MatrixXd::Zero(level_rows[k], nu);
    levels_[k].acceleration = Eigen::VectorXd::Zero(level_rows[k]);
  }
  for (const ModelJoint& joint : model.joints()) {
    if (joint.u_index >= 0 && joint.type != "free") joint_q_u_.emplace_back(joint.q_index, joint.u_index);
  }
  // Only actuated velocities have limits; in contact mode none the free base is driven freely.
  for (int i = 0; i < nu; ++i) {
    if (!model.actuatedVelocities()[static_cast<size_t>(i)] || !options.effort_limits) {
      effort_limit_[i] = std::numeric_limits<double>::infinity();
    }
  }
  for (int i = 0; i < nu; ++i) {
    if (!std::isfinite(effort_limit_[i]) && options.effort_limits) unlimited_.push_back(i);
  }
  unlimited_block_.resize(static_cast<Eigen::Index>(unlimited_.size()), static_cast<Eigen::Index>(unlimited_.size()));
  unlimited_gap_.resize(static_cast<Eigen::Index>(unlimited_.size()));
  jacobian_.resize(6, nu);
  posture_acceleration_.resize(nu);
  bias_forces_.resize(nu);
  zero_ = Eigen::VectorXd::Zero(nu);
}

int OperationalSpaceController::calcTorques(Workspace& workspace, const std::vector<TaskReference>& references,
                                            const PostureReference& posture, Eigen::VectorXd& tau) {
  const double kp = options_.kp, kv = options_.kv;
  const Eigen::VectorXd& q = workspace.getQ();
  const Eigen::VectorXd& u = workspace.getU();
  for (const TaskRows& rows : rows_) {
    const ControlledTask& task = tasks_[rows.task];
    const TaskReference& reference = references[rows.task];
    const Eigen::Isometry3d pose = workspace.findLinkPose(task.link);
    workspace.calcFrameJacobian(task.link, Eigen::Vector3d::Zero(), jacobian_);
    const Vector6d velocity = jacobian_ * u;
    const Vector6d bias = workspace.calcFrameBiasAcceleration(task.link, Eigen::Vector3d::Zero());
    Vector6d wanted;
    wanted.head<3>() = reference.acceleration.head<3>() + kp * OrientationError(reference.orientation, pose.linear()) +
                       kv * (reference.velocity.head<3>() - velocity.head<3>());
    wanted.tail<3>() = reference.acceleration.tail<3>() + kp * (reference.position - pose.translation()) +
                       kv * (reference.velocity.tail<3>() - velocity.tail<3>());
    wanted -= bias;
    PriorityLevel& level = levels_[static_cast<size_t>(rows.level)];
    const int first = task.type == TaskType::kPosition ? 3 : 0;
    const int count = task.type == TaskType::kPose ? 6 : 3;
    level.jacobian.middleRows(rows.first_row, count) = jacobian_.middleRows(first, count);
    level.acceleration.segment(rows.first_row, count) = wanted.segment(first, count);
  }
  // Posture: every joint toward the reference, and a free base's pose too (the tasks above fix it
  // anyway when the pelvis is a pose task).
  posture_acceleration_ = posture.udot + kv * (posture.u - u);
  for (const auto& [qi, ui] : joint_q_u_) posture_acceleration_[ui] += kp * (posture.q[qi] - q[qi]);
  if (free_base_) {
    const Eigen::Quaterniond target(posture.q[0], posture.q[1], posture.q[2], posture.q[3]);
    const Eigen::Quaterniond current(q[0], q[1], q[2], q[3]);
    posture_acceleration_.head<3>() += kp * OrientationError(target.normalized(), current.normalized().toRotationMatrix());
    posture_acceleration_.segment<3>(3) += kp * (posture.q.segment<3>(4) - q.segment<3>(4));
  }
  hierarchy_.calcTorques(workspace, levels_, posture_acceleration_, tau);
  workspace.calcInverseDynamics(zero_, bias_forces_);  // b(q, u) + g(q)
  tau += bias_forces_;
  int saturated = 0;
  unclipped_ = tau;
  for (Eigen::Index i = 0; i < tau.size(); ++i) {
    const double limit = effort_limit_[i];
    if (tau[i] > limit) tau[i] = limit, ++saturated;
    else if (tau[i] < -limit) tau[i] = -limit, ++saturated;
  }
  if (saturated > 0 && !unlimited_.empty()) reconcileUnlimited(workspace, tau);
  return saturated;
}

void OperationalSpaceController::reconcileUnlimited(Workspace& workspace, Eigen::VectorXd& tau) {
  // A clipped joint no longer does what the hierarchy planned, and the unlimited entries (the driven
  // base) were computed to work with the planned torque: left as they are, they push against the
  // clipped joint, its error grows, the plan asks more of it — on the 02_01 walk the waist (50 N·m,
  // where the kinematic motion needs 107) ran away within 20 ms. So re-solve the unlimited entries w
  // for the accelerations the plan wanted there: udot_w(w) is affine in w with slope (A⁻¹)_ww, one
  // O(n) product per unlimited entry, done only on steps where something clipped.
  const int n = static_cast<int>(tau.size());
  const int m = static_cast<int>(unlimited_.size());
  scratch_ = unclipped_ - bias_forces_;
  workspace.calcMassInverseTimes(scratch_, wanted_udot_);
  scratch_ = tau - bias_forces_;
  workspace.calcMassInverseTimes(scratch_, clipped_udot_);
  for (int c = 0; c < m; ++c) {
    scratch_.setZero(n);
    scratch_[unlimited_[static_cast<size_t>(c)]] = 1.0;
    workspace.calcMassInverseTimes(scratch_, column_);
    for (int r = 0; r < m; ++r) unlimited_block_(r, c) = column_[unlimited_[static_cast<size_t>(r)]];
  }
  for (int r = 0; r < m; ++r) {
    const int i = unlimited_[static_cast<size_t>(r)];
    unlimited_gap_[r] = wanted_udot_[i] - clipped_udot_[i];
  }
  unlimited_step_ = unlimited_block_.ldlt().solve(unlimited_gap_);
  for (int r = 0; r < m; ++r) tau[unlimited_[static_cast<size_t>(r)]] += unlimited_step_[r];
}

}  // namespace syn
