// Per-frame inverse kinematics: the robot configuration that best tracks the
// landmark targets of one frame (DESIGN.md, Retarget).
//
// Minimises, over q near the previous frame's solution (warm start),
//   Σ_tasks ‖w_i (p_i(q) − p_i*)‖² + ‖w_i log(R_i(q) R_i*ᵀ)‖²  +  ‖w_p (q_joints − q_ref)‖²
//   + ‖w_c δ‖² + ‖w_a (δ − δ_previous)‖²,   δ = q_joints − q_previous
// with Ceres (Levenberg–Marquardt, dense normal Cholesky), joint limits (and
// the per-frame velocity bound) as bounds on δ enforced by an active set
// around the solves (FrameIk::solve says why), and analytic Jacobians from
// the model (no autodiff through Simbody). The unknown is a velocity-space step δ (size nu) applied
// to the warm start, so a free base's quaternion stays on its manifold:
// q = q_prev ⊕ δ rotates the base by exp(δ_ω) in the ground frame.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "common/model.h"
#include "common/robot_map.h"

namespace syn {

// One tracked link.
struct IkTask {
  int link = -1;                 // Model link index
  TaskType type = TaskType::kPose;
  double weight = 1.0;           // priority weight × task weight
};

// One frame's target for a task; `active` false = no target (weight 0 this frame).
struct IkTarget {
  bool active = false;
  bool has_orientation = true;   // a position-only landmark turns a pose task into a position task
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};

// A robot foot for the contact constraints: its link and sole points (link frame, m).
struct IkFoot {
  int link = -1;
  std::vector<Eigen::Vector3d> sole_points;
};

// What the contact constraints ask of a foot in one frame. Every sole point of every foot stays at
// z >= 0; a planted foot's link is also held exactly at `planted` (flat on the floor, position and yaw
// of its touchdown). kTouchdown: the frame a contact begins — solved as free, then planted where it
// landed (FlatOnFloor), and `planted`/`mode` are updated for the frames that follow.
enum class FootMode : uint8_t { kFree, kTouchdown, kPlanted };
struct FootState {
  FootMode mode = FootMode::kFree;
  Eigen::Isometry3d planted = Eigen::Isometry3d::Identity();
};

// The foot's link pose turned flat (its sole plane horizontal, keeping the yaw) and lowered or raised so
// the sole lies on z = 0, about the sole's centre (which keeps its x, y).
[[nodiscard]] Eigen::Isometry3d FlatOnFloor(const IkFoot& foot, const Eigen::Isometry3d& link_pose);

struct FrameIkOptions {
  // Weight of ‖δ‖ (per rad), δ = this frame's joint step: small, so it only settles joints no task
  // constrains; tracked joints move as the targets say.
  double continuity_weight = 0.01;
  // Weight of ‖δ − δ_previous‖ (per rad): a discrete acceleration penalty that keeps joints the tasks
  // leave nearly free (shoulder yaw and wrist roll under a hand pose) from chattering between equally
  // good solutions, without lagging a smoothly moving joint. The previous step is also where the solver
  // starts. It applies from the second consecutive solve (see FrameIk::forgetHistory). 0.05 tracks
  // exact targets to 0.05 mm / 0.01° (make bench); 0.1 doubles that error.
  double acceleration_weight = 0.05;
  int max_iterations = 50;
  // Stop when the cost changes by less than this fraction (Ceres function_tolerance). Warm-started
  // from the predicted step, exact targets converge in one Gauss-Newton step. Unreachable targets
  // (a scaled human) leave large residuals, where Gauss-Newton's model is poor: after the first step
  // the cost is within 0.1 % of its minimum and tighter tolerances spent 5-10 more, mostly rejected,
  // iterations per frame for no change in the landmark errors over the real-data sweep.
  double function_tolerance = 1e-3;
  double gradient_tolerance = 1e-12;
  double parameter_tolerance = 1e-9;
  // The contact constraints are met by Gauss–Newton steps with exact constraints (constrained_step.h)
  // after the tracking solve: at most this many, stopping when the step is below contact_tolerance
  // (rad or m). Damping λ of those steps: the free base has no posture term, so JᵀJ alone can be singular.
  int max_contact_iterations = 8;
  double contact_tolerance = 1e-7;
  double contact_damping = 1e-4;
  // Each contact step moves no coordinate more than this (rad or m): a trust region.
  double max_contact_step = 0.25;
  // When the constraints are still further than this from met after the steps (m or rad), the frame keeps
  // its tracking solution instead (the violation is reported), rather than a configuration forced far off.
  double max_contact_violation = 0.01;
};

struct FrameIkSummary {
  int iterations = 0;
  double initial_cost = 0.0;
  double final_cost = 0.0;
  bool converged = false;
  double contact_violation = 0.0;  // m or rad the contact constraints could not meet (joint limits, step bound)
};

class FrameIk {
 public:
  // q_reference: the posture target (nq); posture_weight applies to every
  // joint coordinate (not the floating base).
  // feet: the robot's feet for the contact constraints (may be empty: no constraints).
  FrameIk(const Model& model, std::vector<IkTask> tasks, const Eigen::VectorXd& q_reference, double posture_weight,
          const FrameIkOptions& options = {}, std::vector<IkFoot> feet = {});
  ~FrameIk();
  FrameIk(const FrameIk&) = delete;
  FrameIk& operator=(const FrameIk&) = delete;

  // Solves one frame in place: q holds the warm start on entry and the
  // solution on exit. `targets` has one entry per task. With step_time > 0
  // each joint moves at most its URDF velocity limit × step_time.
  // `feet` (one per IkFoot, or null for no contact constraint): the contact constraints rank above every
  // task — they are met exactly when the joint limits and the step bound allow, and the tasks are
  // tracked as well as they can be within them. A kTouchdown foot becomes kPlanted.
  FrameIkSummary solve(const std::vector<IkTarget>& targets, Eigen::VectorXd& q, double step_time = 0.0,
                       std::vector<FootState>* feet = nullptr);

  // The smallest velocity-space change of q that meets the contact constraints, within the joint limits
  // and, when `previous` is given, within the URDF velocity limit × step_time of it. Returns the largest
  // remaining violation (m or rad; 0 when met).
  double project(const std::vector<FootState>& feet, Eigen::VectorXd& q, const Eigen::VectorXd* previous = nullptr,
                 double step_time = 0.0);

  // The contact constraints of a frame linearised at q, for the trajectory refinement: rows
  // c + A x (A: rows × nu, row-major) that should be 0 — a planted foot's pose error, and the height of
  // every sole point of a free foot that is below the floor. Returns the number of rows.
  int linearizeContacts(const std::vector<FootState>& feet, const Eigen::VectorXd& q, Eigen::VectorXd& c,
                        Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>& a);

  // Keeps coordinate q_index at or above `value` in every solve (a branch constraint, tighter than the URDF).
  void restrictLower(int q_index, double value);

  // Each task link's pose at q.
  void taskPoses(const Eigen::VectorXd& q, std::vector<Eigen::Isometry3d>& poses);

  // The robot's feet as given to the constructor, and the lowest sole point height (m) at q.
  const std::vector<IkFoot>& feet() const;
  double lowestSolePoint(const Eigen::VectorXd& q);

  // Solves are taken to be on consecutive frames, each warm-started from the previous solution; call
  // this when the next one is not (after a gap), so no previous step is assumed.
  void forgetHistory();

  // The frame's residual r and its Jacobian J (rows × nu, row-major) at q, with respect to a velocity-space
  // step: the linearisation the trajectory refinement tracks.
  void linearize(const std::vector<IkTarget>& targets, const Eigen::VectorXd& q, Eigen::VectorXd& residual,
                 Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>& jacobian);

  // Position error (m) and angle error (rad) of each task at q (NaN where the
  // target is inactive or has no such part).
  void measureErrors(const std::vector<IkTarget>& targets, const Eigen::VectorXd& q, std::vector<double>& position_error,
                     std::vector<double>& angle_error);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace syn
