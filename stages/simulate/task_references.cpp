#include "stages/simulate/task_references.h"

#include <cmath>

#include "common/error.h"

namespace syn {

std::string_view TargetSourceName(TargetSource source) {
  return source == TargetSource::kLandmarks ? "landmarks" : "kinematic";
}

std::vector<ControlledTask> BindTasks(const RobotMap& map, const Model& model, const MotionData& motion) {
  std::vector<ControlledTask> tasks;
  for (const RobotTask& task : map.tasks) {
    ControlledTask bound;
    bound.landmark = task.landmark;
    bound.link = model.findLinkIndex(task.link);
    if (bound.link < 0) {
      throw DataError(Location::AtLine(map.file, task.line), "link '" + task.link + "' is not in " + model.sourcePath());
    }
    bound.type = task.type;
    bound.priority = task.priority;
    for (size_t i = 0; i < motion.landmark_names.size(); ++i) {
      if (motion.landmark_names[i] == task.landmark) bound.landmark_index = static_cast<int>(i);
    }
    tasks.push_back(bound);
  }
  return tasks;
}

TaskReferences::TaskReferences(const MotionData& motion, const Model& model, const std::vector<ControlledTask>& tasks,
                               TargetSource source)
    : frames_(motion.frames()),
      task_count_(tasks.size()),
      nq_(model.nq()),
      nu_(model.nu()),
      free_base_(model.hasFreeBase()),
      times_(motion.time_s),
      motion_(motion) {
  Workspace workspace(model);
  Eigen::VectorXd q(nq_), u(nu_), udot(nu_);
  Eigen::Matrix<double, 6, Eigen::Dynamic> jacobian(6, nu_);
  references_.resize(static_cast<size_t>(frames_) * task_count_);
  const size_t landmarks = motion.landmark_names.size();
  for (int64_t t = 0; t < frames_; ++t) {
    q = Eigen::Map<const Eigen::VectorXd>(&motion.q[static_cast<size_t>(t * nq_)], nq_);
    u = Eigen::Map<const Eigen::VectorXd>(&motion.u[static_cast<size_t>(t * nu_)], nu_);
    udot = Eigen::Map<const Eigen::VectorXd>(&motion.udot[static_cast<size_t>(t * nu_)], nu_);
    workspace.setQ(q);
    workspace.setU(u);
    for (size_t i = 0; i < task_count_; ++i) {
      const ControlledTask& task = tasks[i];
      TaskReference& reference = references_[static_cast<size_t>(t) * task_count_ + i];
      const Eigen::Isometry3d pose = workspace.findLinkPose(task.link);
      workspace.calcFrameJacobian(task.link, Eigen::Vector3d::Zero(), jacobian);
      reference.position = pose.translation();
      reference.orientation = Eigen::Quaterniond(pose.linear());
      reference.velocity = jacobian * u;
      reference.acceleration = jacobian * udot + workspace.calcFrameBiasAcceleration(task.link, Eigen::Vector3d::Zero());
      if (source == TargetSource::kLandmarks && task.landmark_index >= 0) {
        const double* target = &motion.landmark_targets[(static_cast<size_t>(t) * landmarks +
                                                         static_cast<size_t>(task.landmark_index)) * 7];
        if (std::isfinite(target[0])) reference.position = Eigen::Vector3d(target[0], target[1], target[2]);
        if (std::isfinite(target[3])) {
          reference.orientation = Eigen::Quaterniond(target[3], target[4], target[5], target[6]).normalized();
        }
      }
    }
  }
}

void TaskReferences::shiftAboveLegs(const BalanceShift& shift, const std::vector<ControlledTask>& tasks) {
  for (int64_t t = 0; t < frames_; ++t) {
    const size_t frame = static_cast<size_t>(t);
    for (size_t i = 0; i < task_count_; ++i) {
      if (shift.leg_link[static_cast<size_t>(tasks[i].link)]) continue;
      TaskReference& reference = references_[frame * task_count_ + i];
      reference.position.head<2>() += shift.position[frame];
      reference.velocity.segment<2>(3) += shift.velocity[frame];
      reference.acceleration.segment<2>(3) += shift.acceleration[frame];
    }
  }
  base_shift_ = &shift;
}

void TaskReferences::sample(int64_t frame, double fraction, std::vector<TaskReference>& tasks,
                            PostureReference& posture) const {
  tasks.resize(task_count_);
  const int64_t next = std::min(frame + 1, frames_ - 1);
  const double h = times_[static_cast<size_t>(next)] - times_[static_cast<size_t>(frame)];
  const double s = fraction;
  // Cubic Hermite basis on [0, 1] for the positions; the velocities scale by the interval h.
  const double h00 = 2 * s * s * s - 3 * s * s + 1, h10 = s * s * s - 2 * s * s + s;
  const double h01 = -2 * s * s * s + 3 * s * s, h11 = s * s * s - s * s;
  for (size_t i = 0; i < task_count_; ++i) {
    const TaskReference& a = references_[static_cast<size_t>(frame) * task_count_ + i];
    const TaskReference& b = references_[static_cast<size_t>(next) * task_count_ + i];
    TaskReference& out = tasks[i];
    out.position = h00 * a.position + h10 * h * a.velocity.tail<3>() + h01 * b.position + h11 * h * b.velocity.tail<3>();
    out.orientation = a.orientation.slerp(s, b.orientation);
    out.velocity = (1 - s) * a.velocity + s * b.velocity;
    out.acceleration = (1 - s) * a.acceleration + s * b.acceleration;
  }
  const auto row = [](const std::vector<double>& values, int64_t t, int n) {
    return Eigen::Map<const Eigen::VectorXd>(&values[static_cast<size_t>(t * n)], n);
  };
  posture.q = (1 - s) * row(motion_.q, frame, nq_) + s * row(motion_.q, next, nq_);
  if (free_base_) {
    const auto qa_row = row(motion_.q, frame, nq_), qb_row = row(motion_.q, next, nq_);
    const Eigen::Quaterniond first(qa_row[0], qa_row[1], qa_row[2], qa_row[3]);
    const Eigen::Quaterniond second(qb_row[0], qb_row[1], qb_row[2], qb_row[3]);
    const Eigen::Quaterniond between = first.normalized().slerp(s, second.normalized());
    posture.q[0] = between.w(), posture.q[1] = between.x(), posture.q[2] = between.y(), posture.q[3] = between.z();
  }
  posture.u = (1 - s) * row(motion_.u, frame, nu_) + s * row(motion_.u, next, nu_);
  posture.udot = (1 - s) * row(motion_.udot, frame, nu_) + s * row(motion_.udot, next, nu_);
  if (free_base_ && base_shift_ != nullptr) {
    const auto blend = [&](const std::vector<Eigen::Vector2d>& values) {
      return ((1 - s) * values[static_cast<size_t>(frame)] + s * values[static_cast<size_t>(next)]).eval();
    };
    posture.q.segment<2>(4) += blend(base_shift_->position);
    posture.u.segment<2>(3) += blend(base_shift_->velocity);
    posture.udot.segment<2>(3) += blend(base_shift_->acceleration);
  }
}

}  // namespace syn
