// What the controller tracks, per task and per input frame: the task link's pose, velocity and
// acceleration (angular then linear, in ground), and the joint-space posture reference.
//
// The retargeted motion holds both the landmark targets and the kinematic solution (q, u, udot). The
// velocity and acceleration feedforward always come from the kinematic solution (ẋ = J u,
// ẍ = J udot + J̇ u: smooth, the retargeter's spline), since differentiating 120 Hz capture targets twice
// amplifies their noise. The pose comes from either:
//   kinematic — the link pose the kinematic solution reaches (FK of q): targets the robot can reach,
//               so the simulation reproduces the kinematic mapping dynamically;
//   landmarks — the landmark targets themselves (the paper: the controller tracks the human's scaled
//               landmarks), with the kinematic pose where a target is missing (NaN).
// Between frames poses are interpolated (position by cubic Hermite on the velocities, orientation by
// slerp), velocities and accelerations linearly.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "common/model.h"
#include "common/motion_file.h"
#include "common/robot_map.h"
#include "stages/simulate/balanced_reference.h"

namespace syn {

enum class TargetSource { kKinematic, kLandmarks };
[[nodiscard]] std::string_view TargetSourceName(TargetSource source);

// A robot-map task bound to the model and the motion.
struct ControlledTask {
  std::string landmark;
  int link = -1;            // Model link index
  TaskType type = TaskType::kPose;
  int priority = 1;
  int landmark_index = -1;  // column of the motion's landmark_targets/_error, -1 if the motion has none
};

// Tasks of `map` on `model`, matched to `motion`'s landmark names. DataError for a link the model lacks.
[[nodiscard]] std::vector<ControlledTask> BindTasks(const RobotMap& map, const Model& model, const MotionData& motion);

struct TaskReference {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
  Vector6d velocity = Vector6d::Zero();      // (ω, v) in ground
  Vector6d acceleration = Vector6d::Zero();  // (α, a) in ground
};

struct PostureReference {
  Eigen::VectorXd q, u, udot;
};

class TaskReferences {
 public:
  TaskReferences(const MotionData& motion, const Model& model, const std::vector<ControlledTask>& tasks,
                 TargetSource source);

  // Moves every task not on a leg, and the posture's base, by `shift` (ground mode's balance plan).
  void shiftAboveLegs(const BalanceShift& shift, const std::vector<ControlledTask>& tasks);

  // At `fraction` ∈ [0, 1] of the way from frame `frame` to frame + 1 (fraction 0 at the last frame).
  void sample(int64_t frame, double fraction, std::vector<TaskReference>& tasks, PostureReference& posture) const;

  int64_t frames() const { return frames_; }

 private:
  int64_t frames_ = 0;
  size_t task_count_ = 0;
  int nq_ = 0, nu_ = 0;
  bool free_base_ = false;
  std::vector<double> times_;
  std::vector<TaskReference> references_;  // [frame * task_count + task]
  const BalanceShift* base_shift_ = nullptr;
  const MotionData& motion_;
};

}  // namespace syn
