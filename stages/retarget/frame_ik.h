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
  // The joint terms (these two weights and the posture weight) are for targets the robot cannot meet
  // exactly (a scaled person), where they keep the answer smooth; against exact targets they cost
  // accuracy where the targets barely see a joint (a knee near straight: the same-robot round trip's knees
  // lagged 28° at full weight). Where the previous frame's task cost (FrameIk::taskCost) is below
  // reachable_task_cost the targets are consistent, and all three shrink with √(cost / reachable_task_cost),
  // per joint with the cost of the tasks it moves (FrameIk::regularisationScales),
  // down to min_regularisation_scale of themselves: the regularisation vanishes with the error, the idea of
  // Sugihara's Levenberg–Marquardt IK (IEEE T-RO 27(5), 2011). 1e-4 is a 14 mm residual on one weight-1
  // task. Measured task costs: CMU walks and dances onto the G1 5th percentile 3.5e-4 (02_01) to 1.3e-2
  // (60_10), 1st percentile down to 1.3e-6 (05_20), medians 5.7e-3 .. 0.19; the same-robot G1 motions
  // median 6e-6 .. 4e-5 at full weight, 1e-9 with the shrunk weights. Frames of a scaled person rarely go
  // below it, and those then track tighter: P1 errors on the 32 CMU trials are unchanged (median of
  // medians 35.8 -> 35.4 mm).
  double reachable_task_cost = 1e-4;
  double min_regularisation_scale = 0.03;
  int max_iterations = 50;
  // Stop when the cost changes by less than this fraction (Ceres function_tolerance). Warm-started
  // from the predicted step, exact targets converge in one Gauss-Newton step. Unreachable targets
  // (a scaled human) leave large residuals, where Gauss-Newton's model is poor: after the first step
  // the cost is within 0.1 % of its minimum and tighter tolerances spent 5-10 more, mostly rejected,
  // iterations per frame for no change in the landmark errors over the real-data sweep.
  double function_tolerance = 1e-3;
  // The multiple of the URDF velocity limits solve()'s step_time is scaled by (speed_bound.h).
  double velocity_limit_scale = 1.0;
  double gradient_tolerance = 1e-12;
  double parameter_tolerance = 1e-9;
};

struct FrameIkSummary {
  int iterations = 0;
  double initial_cost = 0.0;
  double final_cost = 0.0;
  bool converged = false;
};

class FrameIk {
 public:
  // q_reference: the posture target (nq); posture_weight applies to every
  // joint coordinate (not the floating base).
  FrameIk(const Model& model, std::vector<IkTask> tasks, const Eigen::VectorXd& q_reference, double posture_weight,
          const FrameIkOptions& options = {});
  ~FrameIk();
  FrameIk(const FrameIk&) = delete;
  FrameIk& operator=(const FrameIk&) = delete;

  // Solves one frame in place: q holds the warm start on entry and the
  // solution on exit. `targets` has one entry per task. With step_time > 0
  // each joint moves at most SpeedPerScaledSecond(its URDF velocity limit) × step_time (speed_bound.h;
  // step_time is the frame's duration times options.velocity_limit_scale).
  FrameIkSummary solve(const std::vector<IkTarget>& targets, Eigen::VectorXd& q, double step_time = 0.0);

  // Solves are taken to be on consecutive frames, each warm-started from the previous solution; call
  // this when the next one is not (after a gap), so no previous step is assumed.
  void forgetHistory();

  // The frame's residual r and its Jacobian J (rows × nu, row-major) at q, with respect to a velocity-space
  // step: the linearisation the trajectory refinement tracks.
  void linearize(const std::vector<IkTarget>& targets, const Eigen::VectorXd& q, Eigen::VectorXd& residual,
                 Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>& jacobian);

  // ½ Σ ‖weighted task residual‖² at q: the cost without the joint terms.
  double taskCost(const std::vector<IkTarget>& targets, const Eigen::VectorXd& q);
  // The same per task (costs: [tasks]).
  void taskCosts(const std::vector<IkTarget>& targets, const Eigen::VectorXd& q, Eigen::VectorXd& costs);

  // The factor on the smoothing weights for a task cost (FrameIkOptions::reachable_task_cost).
  [[nodiscard]] double regularisationScale(double task_cost) const;
  // Per velocity (scales: [nu]), the factor on its smoothing weights at q: regularisationScale of the
  // summed costs of the tasks whose links it moves, but at least the whole frame's to the 4th power (1
  // wherever the targets as a whole are out of reach). Where they are within reach, a joint is smoothed as
  // much as its own tasks are off: an arm whose hand is met exactly is not held back because a foot is
  // not. The IK scales each frame by the previous frame's answer; the trajectory refinement its accelerations.
  void regularisationScales(const std::vector<IkTarget>& targets, const Eigen::VectorXd& q, Eigen::VectorXd& scales);

  // Position error (m) and angle error (rad) of each task at q (NaN where the
  // target is inactive or has no such part).
  void measureErrors(const std::vector<IkTarget>& targets, const Eigen::VectorXd& q, std::vector<double>& position_error,
                     std::vector<double>& angle_error);

 private:
  // solve() without recording the answer's task cost.
  FrameIkSummary solveOnBranch(const std::vector<IkTarget>& targets, Eigen::VectorXd& q, double step_time);

  // One solve from q (solve() may call it twice, see there).
  FrameIkSummary solveOnce(const std::vector<IkTarget>& targets, Eigen::VectorXd& q, double step_time);

  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace syn
