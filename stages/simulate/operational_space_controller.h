// The paper's real-time operational-space controller: the robot map's tasks (Table I) as strict
// priority levels (PrioritizedControl), each task's acceleration a PD law on its reference plus the
// reference acceleration, the joint-space posture last, gravity and Coriolis compensation, and the
// URDF's joint effort limits.
//
//   orientation rows: α* = α_ref + kp · log(R_ref Rᵀ) + kv (ω_ref − ω)
//   position rows:    a* = a_ref + kp (p_ref − p)     + kv (v_ref − v)
//   posture:          a_p = udot_ref + kp (q_ref ⊖ q) + kv (u_ref − u)
//   tau = Σ_k J_k|ᵀ F_k + N ᵀ A a_p + b(q, u) + g(q), each actuated entry clamped to ±effort; when one
//   clips, the unlimited entries (a driven base) are re-solved for the accelerations planned for them.
//
// Contact mode none (the paper's setting): a free base's six velocities are driven like joints (no limit);
// its entries of tau are the wrench the simulation applies to the pelvis.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "common/model.h"
#include "stages/simulate/prioritized_control.h"
#include "stages/simulate/task_references.h"

namespace syn {

struct ControllerOptions {
  double kp = 350.0;  // 1/s², the paper's controller code (task and posture gains)
  double kv = 25.0;   // 1/s, ditto
  PrioritizedControlOptions hierarchy;
  // Clamp actuated torques to the URDF's joint effort (paper: the simulated robot's limits). Off is for
  // diagnosis: how much of a tracking error the limits cause.
  bool effort_limits = true;
};

class OperationalSpaceController {
 public:
  OperationalSpaceController(const Model& model, std::vector<ControlledTask> tasks, const ControllerOptions& options);

  // tau for the state `workspace` holds (setQ and setU done) tracking `references`, after saturation.
  // Returns the number of actuated entries that hit their effort limit.
  int calcTorques(Workspace& workspace, const std::vector<TaskReference>& references, const PostureReference& posture,
                  Eigen::VectorXd& tau);

  const std::vector<ControlledTask>& tasks() const { return tasks_; }
  size_t levelCount() const { return levels_.size(); }
  const PrioritizedControl& hierarchy() const { return hierarchy_; }

 private:
  struct TaskRows {
    size_t task;
    int level;
    Eigen::Index first_row;  // within its level
  };
  ControllerOptions options_;
  std::vector<ControlledTask> tasks_;
  std::vector<TaskRows> rows_;
  std::vector<PriorityLevel> levels_;
  PrioritizedControl hierarchy_;
  bool free_base_;
  Eigen::VectorXd effort_limit_;
  std::vector<std::pair<int, int>> joint_q_u_;  // (q index, u index) of every 1-dof joint
  Eigen::Matrix<double, 6, Eigen::Dynamic> jacobian_;
  Eigen::VectorXd posture_acceleration_, bias_forces_, zero_;
  // Saturation: the unlimited entries (the driven base) re-solved around the clipped joints.
  std::vector<int> unlimited_;
  Eigen::VectorXd unclipped_, scratch_, wanted_udot_, clipped_udot_, column_, unlimited_gap_, unlimited_step_;
  Eigen::MatrixXd unlimited_block_;
  void reconcileUnlimited(Workspace& workspace, Eigen::VectorXd& tau);
};

}  // namespace syn
