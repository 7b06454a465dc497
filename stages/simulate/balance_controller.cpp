#include "stages/simulate/balance_controller.h"

#include <algorithm>
#include <cmath>

namespace syn {
namespace {

// The largest share of the weight the vertical force may be planned at, and the least (a sole pushes,
// it does not pull; a little load keeps the contact from bouncing off).
constexpr double kMinVerticalShare = 0.2, kMaxVerticalShare = 3.0;

// s: the step of the capture-point prediction stepping lands a foot by (a swing lasts 0.3-0.6 s).
constexpr double kPredictionStep = 0.01;
constexpr double kFarBeyondReach = 100.0;  // m

}  // namespace

BalanceController::BalanceController(const Model& model, const RobotMap& map, const BalanceShift& plan,
                                     const std::vector<ControlledTask>& tasks, const BalanceControllerOptions& options)
    : plan_(plan), options_(options), mass_(model.totalMass()), gravity_(model.gravity()) {
  base_link_ = model.freeBaseLink();
  for (size_t i = 0; i < tasks.size(); ++i) {
    if (base_link_ >= 0 && tasks[i].link == base_link_ && tasks[i].type != TaskType::kOrientation) {
      base_task_ = static_cast<int>(i);
      break;
    }
  }
  for (const RobotFoot& foot : map.feet) {
    foot_links_.push_back(model.findLinkIndex(foot.link));
    sole_points_.emplace_back();
    for (const std::array<double, 3>& p : foot.sole_points) sole_points_.back().emplace_back(p[0], p[1], p[2]);
  }
  touching_.resize(foot_links_.size());
  for (const int link : foot_links_) {
    int found = -1;
    for (size_t i = 0; i < tasks.size(); ++i) {
      if (tasks[i].link == link && tasks[i].type != TaskType::kOrientation) found = static_cast<int>(i);
    }
    foot_tasks_.push_back(found);
  }
  was_planted_.assign(foot_links_.size(), true);
  swing_start_.assign(foot_links_.size(), 0.0);
  landing_shift_.assign(foot_links_.size(), Eigen::Vector2d::Zero());
  foot_position_.assign(foot_links_.size(), Eigen::Vector2d::Zero());
  landing_aim_.assign(foot_links_.size(), Eigen::Vector2d::Zero());
  aimed_.assign(foot_links_.size(), false);
  standing_.assign(foot_links_.size(), false);
  jacobian_.resize(6, model.nu());
  // Which base velocities translate the base: their columns of its Jacobian have no angular part (a free
  // joint's last three; a virtual chain's prismatic joints), at any configuration.
  if (base_link_ >= 0) {
    Workspace workspace(model);
    workspace.setQ(model.defaultQ());
    workspace.calcFrameJacobian(base_link_, Eigen::Vector3d::Zero(), jacobian_);
    for (int v = 0; v < model.nu(); ++v) {
      if (model.actuatedVelocities()[static_cast<size_t>(v)]) continue;
      if (jacobian_.col(v).head<3>().norm() < 1e-12 && jacobian_.col(v).tail<3>().norm() > 0.5) {
        translation_velocities_.push_back(v);
      }
    }
  }
  base_force_.resize(static_cast<Eigen::Index>(translation_velocities_.size()));
}

void BalanceController::apply(Workspace& workspace, int64_t frame, double fraction, const int64_t* planted,
                              std::vector<TaskReference>& references, OperationalSpaceController& controller) {
  const size_t a = static_cast<size_t>(frame);
  const size_t b = std::min(a + 1, plan_.com.size() - 1);
  const double s = fraction;
  const auto blend2 = [&](const std::vector<Eigen::Vector2d>& values) { return ((1 - s) * values[a] + s * values[b]).eval(); };
  const auto blend1 = [&](const std::vector<double>& values) { return (1 - s) * values[a] + s * values[b]; };
  const Eigen::Vector2d com_plan = blend2(plan_.com) + plan_offset_, velocity_plan = blend2(plan_.com_velocity);
  const Eigen::Vector2d acceleration_plan = blend2(plan_.com_acceleration), zmp_plan = blend2(plan_.zmp) + plan_offset_;
  const double omega = 1.0 / std::sqrt(blend1(plan_.eta));
  const Eigen::Vector3d com = workspace.findCenterOfMass();
  const Eigen::Vector3d velocity = workspace.calcCentroidalMomentum().tail<3>() / mass_;
  const Eigen::Vector2d capture_point = com.head<2>() + velocity.head<2>() / omega;

  // The standing soles: the points on the floor of feet planted in the source; and of any other touching
  // foot while the capture point lies outside those (CMU 02_01 lifted its trailing foot while the landing
  // one touched only at its heel's corner, and the robot fell over that corner).
  support_.clear();
  for (size_t f = 0; f < foot_links_.size(); ++f) {
    const Eigen::Isometry3d pose = workspace.findLinkPose(foot_links_[f]);
    foot_position_[f] = pose.translation().head<2>();
    touching_[f].clear();
    for (const Eigen::Vector3d& local : sole_points_[f]) {
      const Eigen::Vector3d point = pose * local;
      if (point.z() < options_.touch_height) touching_[f].emplace_back(point.x(), point.y());
    }
    standing_[f] = !touching_[f].empty() && planted[f] != 0;
    if (standing_[f]) support_.insert(support_.end(), touching_[f].begin(), touching_[f].end());
  }
  bool captured = false;
  if (!support_.empty()) {
    ConvexHull(support_, hull_);
    captured = (ClosestInPolygon(capture_point, hull_) - capture_point).squaredNorm() < 1e-12;
  }
  for (size_t f = 0; f < foot_links_.size() && !captured; ++f) {
    if (!standing_[f]) support_.insert(support_.end(), touching_[f].begin(), touching_[f].end());
  }
  state_ = BalanceSample{};
  command_ = BalanceCommand{};
  const double now = (1 - s) * plan_.time[a] + s * plan_.time[b];
  if (support_.empty() || base_link_ < 0 || translation_velocities_.empty()) {
    controller.clearCentreOfMassLevel();
    // In a flight the task targets stay where the stepping put them: without its landing shifts, swing lift
    // and the plan's offset they jumped back by up to the offset (tens of cm) for the flight's few ms.
    if (options_.max_step_shift > 0 && base_link_ >= 0) placeReferences(now, a, planted, references);
    reportLanding(fraction);
    return;
  }
  ConvexHull(support_, hull_);

  // Horizontal: the capture point back to the plan's through a zmp the soles can push.
  const Eigen::Vector2d capture_error = (com.head<2>() - com_plan) + (velocity.head<2>() - velocity_plan) / omega;
  const Eigen::Vector2d wanted_zmp = zmp_plan + (1 + options_.capture_gain / omega) * capture_error;
  const Eigen::Vector2d commanded_zmp = ClosestInPolygon(wanted_zmp, hull_);
  state_.balancing = true;
  state_.capture_error = capture_error.norm();
  state_.zmp_shortfall = (wanted_zmp - commanded_zmp).norm();
  state_.plan_shortfall = (ClosestInPolygon(zmp_plan, hull_) - zmp_plan).norm();
  state_.support_points = static_cast<int>(support_.size());
  state_.standing_both = std::count(standing_.begin(), standing_.end(), true) >= 2;
  const Eigen::Vector2d horizontal =
      acceleration_plan + omega * omega * ((com.head<2>() - com_plan) - (commanded_zmp - zmp_plan));
  // Vertical: a PD on the plan's centre-of-mass height.
  const double height_acceleration = blend1(plan_.com_height_acceleration) +
                                     options_.kp * (blend1(plan_.com_height) - com.z()) +
                                     options_.kv * (blend1(plan_.com_height_velocity) - velocity.z());
  Eigen::Vector3d force;
  force.z() = std::clamp(mass_ * (gravity_ + height_acceleration), kMinVerticalShare * mass_ * gravity_,
                          kMaxVerticalShare * mass_ * gravity_);
  force.head<2>() = mass_ * horizontal;
  const double tangential = force.head<2>().norm(), cone = options_.friction * force.z();
  if (tangential > cone) force.head<2>() *= cone / tangential;
  command_ = {com.head<2>(), capture_error, zmp_plan, wanted_zmp, commanded_zmp, force};

  // The generalized forces that force makes on the translating base velocities: their Jacobian columns
  // (pure translations) dotted with it.
  workspace.calcFrameJacobian(base_link_, Eigen::Vector3d::Zero(), jacobian_);
  for (size_t i = 0; i < translation_velocities_.size(); ++i) {
    base_force_[static_cast<Eigen::Index>(i)] = jacobian_.col(translation_velocities_[i]).tail<3>().dot(force);
  }
  controller.setCentreOfMassLevel(translation_velocities_, base_force_);
  if (options_.max_step_shift > 0) {
    step(now, a, planted, capture_error, zmp_plan, omega);
    placeReferences(now, a, planted, references);
  }

  reportLanding(fraction);
  if (base_task_ >= 0) {
    TaskReference& reference = references[static_cast<size_t>(base_task_)];
    reference.position.head<2>() = com.head<2>() + (reference.position.head<2>() - com_plan);
    reference.velocity.segment<2>(3) = velocity.head<2>() + (reference.velocity.segment<2>(3) - velocity_plan);
    reference.acceleration.segment<2>(3) = horizontal + (reference.acceleration.segment<2>(3) - acceleration_plan);
  }
}

void BalanceController::reportLanding(double fraction) {
  // Only the calls at a frame (fraction 0) are recorded. A landing seen between frames (at a call after one
  // with no sole on the floor, which does not step: a brisk walk's flight) waits for the next frame's.
  if (fraction != 0.0) return;
  state_.landing_miss = unreported_miss_;
  unreported_miss_ = -1;
}

Eigen::Vector2d BalanceController::PredictedCaptureError(const Eigen::Vector2d& capture_error,
                                                         const Eigen::Vector2d& zmp_plan, double omega, double remaining) const {
  // The closed loop ė = ω (e − Δp(e)), Δp(e) = clamp(p_plan + (1 + k/ω) e) − p_plan, by explicit Euler in
  // steps of at most kPredictionStep. (Holding the zero-moment point where it is now instead, an error the
  // ankles were already returning was predicted to run away the other way, e^(ωT) times what feedback
  // leaves of it, and feet unneeded at their 15 cm cap swung to either side of their plan.)
  const int steps = std::max(1, static_cast<int>(std::ceil(remaining / kPredictionStep)));
  const double h = remaining / steps, gain = 1.0 + options_.capture_gain / omega;
  Eigen::Vector2d error = capture_error;
  for (int i = 0; i < steps; ++i) {
    const Eigen::Vector2d zmp_error = ClosestInPolygon(zmp_plan + gain * error, hull_) - zmp_plan;
    error += h * omega * (error - zmp_error);
    // Far past any step's reach already (the shift is capped): stop before a long swing (a dance's foot in
    // the air for seconds) overflows it.
    if (error.squaredNorm() > kFarBeyondReach * kFarBeyondReach) break;
  }
  return error;
}

void BalanceController::step(double now, size_t frame, const int64_t* planted, const Eigen::Vector2d& capture_error,
                             const Eigen::Vector2d& zmp_plan, double omega) {
  for (size_t f = 0; f < foot_links_.size(); ++f) {
    if (foot_tasks_[f] < 0) continue;
    if (planted[f] != 0) {
      if (!was_planted_[f]) plan_offset_ += landing_shift_[f];  // it landed: the plan walks on from there
      if (aimed_[f]) {
        unreported_miss_ = std::max(unreported_miss_, (foot_position_[f] - landing_aim_[f]).norm());
        aimed_[f] = false;
      }
      landing_shift_[f].setZero();
      was_planted_[f] = true;
      continue;
    }
    if (was_planted_[f]) swing_start_[f] = now;
    was_planted_[f] = false;
    const double landing = SwingLanding(f, frame, now);
    if (landing < 0) continue;
    Eigen::Vector2d shift = PredictedCaptureError(capture_error, zmp_plan, omega, landing - now);
    state_.stepping = true;
    state_.landing_needed = std::max(state_.landing_needed, shift.norm());
    if (shift.norm() > options_.max_step_shift) shift *= options_.max_step_shift / shift.norm();
    landing_shift_[f] = shift;
  }
}

double BalanceController::SwingLanding(size_t foot, size_t frame, double now) const {
  const int64_t touchdown = plan_.next_touchdown[foot][frame];
  if (touchdown < 0) return -1;
  const double landing = plan_.time[static_cast<size_t>(touchdown)];
  return landing > now ? landing : -1;
}

void BalanceController::placeReferences(double now, size_t frame, const int64_t* planted, std::vector<TaskReference>& references) {
  for (size_t f = 0; f < foot_links_.size(); ++f) {
    if (foot_tasks_[f] < 0 || planted[f] != 0 || was_planted_[f]) continue;
    const double landing = SwingLanding(f, frame, now);
    if (landing < 0) continue;
    const double duration = std::max(landing - swing_start_[f], 1e-6);
    const double progress = std::clamp((now - swing_start_[f]) / duration, 0.0, 1.0);
    TaskReference& foot = references[static_cast<size_t>(foot_tasks_[f])];
    foot.position.head<2>() += progress * progress * (3 - 2 * progress) * landing_shift_[f];
    // The lift's rate and acceleration go into the feedforward with it (the landing shift's do not: it is
    // re-predicted every step, and its feedforward made no walk stay up longer).
    const double start = plan_.airborne_start[f][frame], end = plan_.airborne_end[f][frame];
    if (start >= 0 && end > start) {
      const double span = end - start, phase = M_PI * std::clamp((now - start) / span, 0.0, 1.0);
      foot.position.z() += options_.swing_lift * std::sin(phase);
      foot.velocity[5] += options_.swing_lift * M_PI / span * std::cos(phase);
      foot.acceleration[5] -= options_.swing_lift * (M_PI / span) * (M_PI / span) * std::sin(phase);
    }
    landing_aim_[f] = foot.position.head<2>() + plan_offset_;
    aimed_[f] = true;
  }
  for (TaskReference& reference : references) reference.position.head<2>() += plan_offset_;
}

}  // namespace syn
