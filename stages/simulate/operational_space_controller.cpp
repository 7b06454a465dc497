#include "stages/simulate/operational_space_controller.h"

#include <algorithm>
#include <cmath>
#include <map>

namespace syn {
namespace {

// Rounds of the joint-limit active set per control step: each round adds the walls the last solution
// crosses; a knee and an ankle pressed together take two.
constexpr int kLimitPasses = 3;
// Rounds of re-solving the free torques after some clipped (see redistributeClippedTorque).
constexpr int kClipRounds = 3;
// Levels 0-3: the joint-limit walls, the standing feet, the swinging feet's headings and the centre of mass
// (the last three ground mode; empty otherwise).
constexpr int kStanceLevel = 1, kSwingingFeetLevel = 2, kCentreOfMassLevel = 3, kFirstTaskLevel = 4;
// The swinging feet's rows are few and far from dependent on the held feet's (a swinging leg moves its foot
// whatever the stance leg does); this cutoff only keeps out a row with no authority left.
constexpr double kSwingingFeetCutoff = 1e-6;

// Rows of a task's Jacobian in TaskRowBits's layout: the one that turns its link about the vertical (ground
// z), the third of the angular rows, which come first in pose and orientation tasks alike; and a pose task's
// horizontal position rows (x, y in ground; z, the height, follows).
constexpr int kHeadingRow = 2, kPositionXRow = 3, kPositionYRow = 4;

// A joint with a limit within 0.2 rad of its zero: a knee (G1 −0.087 … 2.88 rad) or an elbow whose zero
// is the straight limb, where the limit is the straight configuration and past it lies the mirrored
// branch. Walls on every limited joint were tried: on 16 CMU walks the light wrists and the narrow
// ankle rolls (±0.26 rad), pressed against their walls, left the tasks nearly singular and 3 runs
// diverged, where with walls on these joints alone none did.
bool IsBranchJoint(double lower, double upper) {
  constexpr double kNearZero = 0.2;
  return std::abs(lower) < kNearZero || std::abs(upper) < kNearZero;
}

// Rotation vector of r_target · rᵀ (ground frame): the angular error that takes r to r_target.
Eigen::Vector3d OrientationError(const Eigen::Quaterniond& target, const Eigen::Matrix3d& rotation) {
  Eigen::Quaterniond difference = target * Eigen::Quaterniond(rotation).conjugate();
  if (difference.w() < 0) difference.coeffs() = -difference.coeffs();  // the short way round
  const Eigen::AngleAxisd angle_axis(difference);
  return angle_axis.angle() * angle_axis.axis();
}

}  // namespace

unsigned OperationalSpaceController::keptTaskRows(size_t task) const {
  // The task's rows sit in its level in bit order, from first_row on.
  const TaskRows& rows = rows_[task];
  const unsigned bits = TaskRowBits(tasks_[task].type);
  unsigned kept = 0;
  int row = static_cast<int>(rows.first_row);
  for (int r = 0; r < 6; ++r) {
    if (!((bits >> r) & 1u)) continue;
    if (hierarchy_.rowKept(static_cast<size_t>(rows.level), row++)) kept |= 1u << r;
  }
  for (size_t r = 0; r < swinging_rows_.size(); ++r) {
    if (swinging_rows_[r].task == task && hierarchy_.rowKept(static_cast<size_t>(kSwingingFeetLevel), static_cast<int>(r))) {
      kept |= 1u << swinging_rows_[r].row;
    }
  }
  return kept;
}

int ClipToEffort(const Eigen::VectorXd& limit, Eigen::VectorXd& tau) {
  int clipped = 0;
  for (Eigen::Index i = 0; i < tau.size(); ++i) {
    if (tau[i] > limit[i]) tau[i] = limit[i], ++clipped;
    else if (tau[i] < -limit[i]) tau[i] = -limit[i], ++clipped;
  }
  return clipped;
}

OperationalSpaceController::OperationalSpaceController(const Model& model, std::vector<ControlledTask> tasks,
                                                       const ControllerOptions& options)
    : options_(options),
      tasks_(std::move(tasks)),
      hierarchy_(options.hierarchy),
      mass_(model),
      free_base_(model.hasFreeBase()),
      effort_limit_(model.effortLimit()) {
  const int nu = model.nu();
  // One level per distinct priority, highest (smallest number) first.
  std::map<int, int> level_of_priority;
  for (const ControlledTask& task : tasks_) level_of_priority[task.priority] = 0;
  int next_level = kFirstTaskLevel;
  for (auto& [priority, level] : level_of_priority) level = next_level++;
  std::vector<Eigen::Index> level_rows(level_of_priority.size() + kFirstTaskLevel, 0);
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
    if (joint.u_index < 0 || joint.type == "free" || !options.joint_limits) continue;
    if (!model.actuatedVelocities()[static_cast<size_t>(joint.u_index)]) continue;  // a virtual base's joints
    const double lower = model.qLower()[joint.q_index], upper = model.qUpper()[joint.q_index];
    if (std::isfinite(lower) && std::isfinite(upper) && upper > lower && IsBranchJoint(lower, upper)) {
      limited_joints_.push_back({joint.q_index, joint.u_index, lower, upper});
    }
  }
  active_limits_.reserve(limited_joints_.size());
  // Only actuated velocities have limits; in contact mode none the free base is driven freely.
  for (int i = 0; i < nu; ++i) {
    if (!model.actuatedVelocities()[static_cast<size_t>(i)] || !options.effort_limits) {
      effort_limit_[i] = std::numeric_limits<double>::infinity();
    }
  }
  free_.reserve(static_cast<size_t>(nu));
  swinging_rows_.reserve(3 * tasks_.size());
  levels_[kSwingingFeetLevel].independence_cutoff = kSwingingFeetCutoff;
  jacobian_.resize(6, nu);
  posture_acceleration_.resize(nu);
  bias_forces_.resize(nu);
  zero_ = Eigen::VectorXd::Zero(nu);
}

int OperationalSpaceController::calcTorques(Workspace& workspace, const std::vector<TaskReference>& references,
                                            const PostureReference& posture, Eigen::VectorXd& tau) {
  const double kp = options_.kp, kv = options_.kv;
  mass_.factor(workspace);
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
  workspace.calcInverseDynamics(zero_, bias_forces_);  // b(q, u) + g(q)
  PriorityLevel& centre_of_mass = levels_[kCentreOfMassLevel];
  const Eigen::Index rows = com_level_ ? static_cast<Eigen::Index>(base_velocities_.size()) : 0;
  centre_of_mass.jacobian.resize(rows, workspace.model().nu());
  centre_of_mass.acceleration.resize(rows);
  for (Eigen::Index r = 0; r < rows; ++r) {
    const int i = base_velocities_[static_cast<size_t>(r)];
    centre_of_mass.jacobian.row(r) = mass_.mass().row(i);
    centre_of_mass.acceleration[r] = base_force_[r] - bias_forces_[i];
  }
  PriorityLevel& stance = levels_[kStanceLevel];
  if (!stance_level_) {
    stance.jacobian.resize(0, workspace.model().nu());
    stance.acceleration.resize(0);
  }
  fillSwingingFeetLevel(workspace.model().nu());
  active_limits_.clear();
  PriorityLevel& walls = levels_[0];
  walls.jacobian.resize(0, workspace.model().nu());
  walls.acceleration.resize(0);
  for (int pass = 0; pass < kLimitPasses; ++pass) {
    hierarchy_.calcTorques(workspace, mass_, levels_, posture_acceleration_, tau);
    if (!addViolatedWalls(workspace, tau)) break;
    const Eigen::Index count = static_cast<Eigen::Index>(active_limits_.size());
    walls.jacobian.setZero(count, workspace.model().nu());
    walls.acceleration.resize(count);
    for (Eigen::Index r = 0; r < count; ++r) {
      walls.jacobian(r, active_limits_[static_cast<size_t>(r)].u_index) = 1.0;
      walls.acceleration[r] = active_limits_[static_cast<size_t>(r)].acceleration;
    }
    if (pass + 1 == kLimitPasses) hierarchy_.calcTorques(workspace, mass_, levels_, posture_acceleration_, tau);
  }
  tau += bias_forces_;
  unclipped_ = tau;
  const int saturated = ClipToEffort(effort_limit_, tau);
  if (saturated > 0) redistributeClippedTorque(tau);
  return saturated;
}

void OperationalSpaceController::setCentreOfMassLevel(const std::vector<int>& base_velocities,
                                                      const Eigen::VectorXd& base_force) {
  base_velocities_ = base_velocities;
  base_force_ = base_force;
  com_level_ = true;
}

void OperationalSpaceController::clearCentreOfMassLevel() { com_level_ = false; }

void OperationalSpaceController::setStanceLevel(const Eigen::MatrixXd& jacobian, const Eigen::VectorXd& acceleration) {
  levels_[kStanceLevel].jacobian = jacobian;
  levels_[kStanceLevel].acceleration = acceleration;
  stance_level_ = true;
}

void OperationalSpaceController::clearStanceLevel() { stance_level_ = false; }

void OperationalSpaceController::setSwingingFeet(const std::vector<SwingingFoot>& feet) {
  swinging_rows_.clear();
  for (const SwingingFoot& foot : feet) {
    if (tasks_[foot.task].type == TaskType::kPosition) continue;
    swinging_rows_.push_back({foot.task, kHeadingRow});
    if (!foot.landing || tasks_[foot.task].type != TaskType::kPose) continue;
    swinging_rows_.push_back({foot.task, kPositionXRow});
    swinging_rows_.push_back({foot.task, kPositionYRow});
  }
}

void OperationalSpaceController::fillSwingingFeetLevel(int nu) {
  // Each row and its wanted acceleration as the task loop just wrote them at the task's own priority (an
  // orientation task's rows are its heading's three; a pose task's the angular then the position rows).
  PriorityLevel& level = levels_[kSwingingFeetLevel];
  const Eigen::Index rows = static_cast<Eigen::Index>(swinging_rows_.size());
  level.jacobian.resize(rows, nu);
  level.acceleration.resize(rows);
  for (Eigen::Index r = 0; r < rows; ++r) {
    const SwingingRow& swinging = swinging_rows_[static_cast<size_t>(r)];
    const TaskRows& task = rows_[swinging.task];
    const PriorityLevel& own = levels_[static_cast<size_t>(task.level)];
    level.jacobian.row(r) = own.jacobian.row(task.first_row + swinging.row);
    level.acceleration[r] = own.acceleration[task.first_row + swinging.row];
  }
}

void OperationalSpaceController::calcAcceleration(const Eigen::VectorXd& tau, Eigen::VectorXd& udot) const {
  udot = tau - bias_forces_;
  mass_.solveInPlace(udot);
}

bool OperationalSpaceController::addViolatedWalls(Workspace& workspace, const Eigen::VectorXd& task_torques) {
  if (limited_joints_.empty()) return false;
  // The torques exclude gravity and velocity terms, so A⁻¹ Γ is the acceleration they plan.
  planned_udot_ = task_torques;
  mass_.solveInPlace(planned_udot_);
  const Eigen::VectorXd& q = workspace.getQ();
  const Eigen::VectorXd& u = workspace.getU();
  bool added = false;
  for (const LimitedJoint& joint : limited_joints_) {
    const double position = q[joint.q_index], velocity = u[joint.u_index];
    const auto already = std::find_if(active_limits_.begin(), active_limits_.end(),
                                      [&](const ActiveLimit& active) { return active.u_index == joint.u_index; });
    if (already != active_limits_.end()) continue;
    const double planned = planned_udot_[joint.u_index];
    const double omega = options_.limit_frequency;
    const double lower_wall = omega * omega * (joint.lower - position) - 2.0 * omega * velocity;
    const double upper_wall = omega * omega * (joint.upper - position) - 2.0 * omega * velocity;
    if (planned < lower_wall) {
      active_limits_.push_back({joint.u_index, lower_wall}), added = true;
    } else if (planned > upper_wall) {
      active_limits_.push_back({joint.u_index, upper_wall}), added = true;
    }
  }
  return added;
}

void OperationalSpaceController::redistributeClippedTorque(Eigen::VectorXd& tau) {
  // A clipped joint no longer does what the hierarchy planned, and every other torque was computed to
  // work with the planned one: left as they are, they push against the clipped joint, its error grows
  // and the plan asks still more of it — on the 02_01 walk the waist (50 N·m, where the kinematic motion
  // needs 107) ran away within 20 ms. So re-solve every entry still inside its limit (the driven base
  // too) for the accelerations the plan wanted there: udot_F(τ_F) is affine with slope (A⁻¹)_FF, one
  // O(n) product per free entry, done only on steps where something clipped. An entry the re-solve
  // pushes past its own limit is clipped in turn and the rest solved again, at most kClipRounds times.
  // Only the clipped joints then miss their planned acceleration. Re-solving the base alone (what this
  // replaced) left 3 of 16 CMU walks diverging and 8 within 3° of the kinematic motion; this, 1 and 9.
  const int n = static_cast<int>(tau.size());
  scratch_ = unclipped_ - bias_forces_;
  wanted_udot_ = scratch_;
  mass_.solveInPlace(wanted_udot_);
  for (int round = 0; round < kClipRounds; ++round) {
    free_.clear();
    for (int i = 0; i < n; ++i) {
      if (std::abs(tau[i]) < effort_limit_[i]) free_.push_back(i);
    }
    const int m = static_cast<int>(free_.size());
    scratch_ = tau - bias_forces_;
    clipped_udot_ = scratch_;
    mass_.solveInPlace(clipped_udot_);
    free_block_.resize(m, m);
    free_gap_.resize(m);
    for (int c = 0; c < m; ++c) {
      scratch_.setZero(n);
      scratch_[free_[static_cast<size_t>(c)]] = 1.0;
      column_ = scratch_;
      mass_.solveInPlace(column_);
      for (int r = 0; r < m; ++r) free_block_(r, c) = column_[free_[static_cast<size_t>(r)]];
    }
    for (int r = 0; r < m; ++r) free_gap_[r] = wanted_udot_[free_[static_cast<size_t>(r)]] - clipped_udot_[free_[static_cast<size_t>(r)]];
    free_step_ = free_block_.ldlt().solve(free_gap_);
    bool clipped = false;
    for (int r = 0; r < m; ++r) {
      const int i = free_[static_cast<size_t>(r)];
      tau[i] += free_step_[r];
      if (tau[i] > effort_limit_[i]) tau[i] = effort_limit_[i], clipped = true;
      else if (tau[i] < -effort_limit_[i]) tau[i] = -effort_limit_[i], clipped = true;
    }
    if (!clipped) break;
  }
}

}  // namespace syn
