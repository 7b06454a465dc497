#include "stages/retarget/foot_targets.h"

#include <algorithm>
#include <cmath>
#include <limits>

namespace syn {
namespace {

Eigen::Isometry3d TargetPose(const IkTarget& target) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.translation() = target.position;
  if (target.has_orientation) pose.linear() = target.orientation.normalized().toRotationMatrix();
  return pose;
}

double Smoothstep(double x) {
  x = std::clamp(x, 0.0, 1.0);
  return x * x * (3 - 2 * x);
}

// Moves `target` the fraction `weight` of the way to `planted`.
void BlendToward(const Eigen::Isometry3d& planted, double weight, IkTarget& target) {
  target.position = (1 - weight) * target.position + weight * planted.translation();
  if (target.has_orientation) {
    target.orientation = target.orientation.normalized().slerp(weight, Eigen::Quaterniond(planted.linear())).normalized();
  }
}

// The lowest sole point of the foot at the target pose (z, m).
double LowestSolePoint(const IkFoot& foot, const IkTarget& target) {
  const Eigen::Isometry3d pose = TargetPose(target);
  double lowest = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& point : foot.sole_points) lowest = std::min(lowest, (pose * point).z());
  return lowest;
}

// The foot's pose in a contact phase: the planted (flat) pose, pitched as the source foot is about the
// sole edge it rolls on — the toe edge when the heel is up (pitch > 0: about the link's y axis, x toward
// −z), the heel edge when the toe is up — so that edge stays where it was planted and no sole point goes
// below the floor. Pitches within `dead_zone` of flat are flat.
Eigen::Isometry3d RolledPose(const IkFoot& foot, const Eigen::Isometry3d& planted, const IkTarget& source, double dead_zone) {
  if (!source.has_orientation || foot.sole_points.empty()) return planted;
  const Eigen::Matrix3d relative = planted.linear().transpose() * source.orientation.normalized().toRotationMatrix();
  const double pitch = std::atan2(relative(0, 2), relative(2, 2));
  const double rolled = std::copysign(std::max(0.0, std::abs(pitch) - dead_zone), pitch);
  if (rolled == 0.0) return planted;
  Eigen::Vector3d edge = foot.sole_points.front();
  for (const Eigen::Vector3d& point : foot.sole_points) {
    if (rolled > 0 ? point.x() > edge.x() : point.x() < edge.x()) edge = point;
  }
  edge.y() = 0;
  Eigen::Isometry3d pivot = Eigen::Isometry3d::Identity();
  pivot.linear() = Eigen::AngleAxisd(rolled, Eigen::Vector3d::UnitY()).toRotationMatrix();
  pivot.translation() = edge - pivot.linear() * edge;
  return planted * pivot;
}

// The tilt of a target pose's sole from flat (rad): the angle between its link z axis and the world's.
double Tilt(const IkTarget& target) {
  if (!target.has_orientation) return 0.0;
  const Eigen::Vector3d z = target.orientation.normalized().toRotationMatrix().col(2);
  return std::acos(std::clamp(z.z(), -1.0, 1.0));
}

void SetPose(const Eigen::Isometry3d& pose, IkTarget& target) {
  target.position = pose.translation();
  if (target.has_orientation) target.orientation = Eigen::Quaterniond(pose.linear());
}

}  // namespace

void ShapeFootTargets(const std::vector<IkFoot>& feet, const std::vector<int>& foot_task, const FootContacts& contacts,
                      const std::vector<double>& time_s, const FootTargetOptions& options,
                      std::vector<std::vector<IkTarget>>& frame_targets) {
  const int64_t frames = static_cast<int64_t>(frame_targets.size());
  for (size_t f = 0; f < feet.size() && f < foot_task.size(); ++f) {
    const int task = foot_task[f];
    if (task < 0 || static_cast<int>(f) >= contacts.feet) continue;
    auto target_at = [&](int64_t t) -> IkTarget* {
      std::vector<IkTarget>& frame = frame_targets[static_cast<size_t>(t)];
      return static_cast<size_t>(task) < frame.size() && frame[static_cast<size_t>(task)].active
                 ? &frame[static_cast<size_t>(task)]
                 : nullptr;
    };
    // Each phase's planted pose: its flattest targeted frame's pose, flat on the floor. In the phase the
    // foot holds it, rolled about a sole edge as the source rolls (RolledPose); `first`/`last` are the
    // poses at the phase's ends, which the swings blend from and to.
    std::vector<ContactPhase> phases;
    std::vector<Eigen::Isometry3d> planted, first, last;
    for (const ContactPhase& phase : contacts.phases) {
      if (phase.foot != static_cast<int>(f)) continue;
      int64_t flattest = -1;
      for (int64_t t = phase.begin; t < phase.end; ++t) {
        if (const IkTarget* target = target_at(t)) {
          if (flattest < 0 || Tilt(*target) < Tilt(*target_at(flattest))) flattest = t;
        }
      }
      if (flattest < 0) continue;
      const IkTarget& reference = *target_at(flattest);
      Eigen::Isometry3d pose = TargetPose(reference);
      if (reference.has_orientation) pose = FlatOnFloor(feet[f], pose);
      phases.push_back(phase);
      planted.push_back(pose);
      first.push_back(pose);
      last.push_back(pose);
    }
    for (size_t k = 0; k < phases.size(); ++k) {
      for (int64_t t = phases[k].begin; t < phases[k].end; ++t) {
        if (const IkTarget* target = target_at(t)) {
          first[k] = RolledPose(feet[f], planted[k], *target, options.roll_dead_zone);
          break;
        }
      }
      for (int64_t t = phases[k].end - 1; t >= phases[k].begin; --t) {
        if (const IkTarget* target = target_at(t)) {
          last[k] = RolledPose(feet[f], planted[k], *target, options.roll_dead_zone);
          break;
        }
      }
    }
    // The swings between phases (and before the first, after the last): blend out of the phase before,
    // into the phase after, each over at most half the swing; raise what would be below the floor.
    for (size_t k = 0; k <= phases.size(); ++k) {
      const int64_t swing_begin = k == 0 ? 0 : phases[k - 1].end;
      const int64_t swing_end = k == phases.size() ? frames : phases[k].begin;
      const double lifted_at = k == 0 ? -std::numeric_limits<double>::infinity() : time_s[static_cast<size_t>(swing_begin - 1)];
      const double lands_at = k == phases.size() ? std::numeric_limits<double>::infinity() : time_s[static_cast<size_t>(swing_end)];
      const double window = std::min(options.approach, 0.5 * (lands_at - lifted_at));
      for (int64_t t = swing_begin; t < swing_end; ++t) {
        IkTarget* target = target_at(t);
        if (target == nullptr) continue;
        const double now = time_s[static_cast<size_t>(t)];
        if (window > 0 && now - lifted_at < window) {
          const double w = Smoothstep(1 - (now - lifted_at) / window);
          BlendToward(last[k - 1], w, *target);
        } else if (window > 0 && lands_at - now < window) {
          const double w = Smoothstep(1 - (lands_at - now) / window);
          BlendToward(first[k], w, *target);
        }
        const double lowest = LowestSolePoint(feet[f], *target);
        if (lowest < 0) target->position.z() -= lowest;
      }
      if (k == phases.size()) break;
      for (int64_t t = phases[k].begin; t < phases[k].end; ++t) {
        IkTarget* target = target_at(t);
        if (target == nullptr) continue;
        SetPose(RolledPose(feet[f], planted[k], *target, options.roll_dead_zone), *target);
      }
    }
  }
}

}  // namespace syn
