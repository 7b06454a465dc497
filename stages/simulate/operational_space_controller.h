// The paper's real-time operational-space controller: the robot map's tasks (Table I) as strict
// priority levels (PrioritizedControl), each task's acceleration a PD law on its reference plus the
// reference acceleration, the joint-space posture last, gravity and Coriolis compensation, and the
// URDF's joint effort limits.
//
//   orientation rows: α* = α_ref + kp · log(R_ref Rᵀ) + kv (ω_ref − ω)
//   position rows:    a* = a_ref + kp (p_ref − p)     + kv (v_ref − v)
//   posture:          a_p = udot_ref + kp (q_ref ⊖ q) + kv (u_ref − u)
//   tau = Σ_k J_k|ᵀ F_k + N ᵀ A a_p + b(q, u) + g(q), each actuated entry clamped to ±effort; when one
//   clips, every entry still inside its limit is re-solved for the acceleration planned for it.
//
// Joint limits of the branch joints (knees, and elbows whose zero is the straight arm: a limit within
// 0.2 rad of zero) rank above every task. The simulated robot has no mechanical stops, and without them a
// task can carry a straightening knee through the singularity onto its mirrored branch (the foot stays
// on target, the knee bends backwards: 50° off on CMU 02_01). Each such joint has a wall at each limit,
// a critically damped spring of natural frequency ω: q̈ ≥ ω² (lower − q) − 2ω u and
// q̈ ≤ ω² (upper − q) − 2ω u. Far from a limit the bound is far below anything planned; a joint heading
// for it at speed v is braked from about v/ω away and comes to rest on the limit without crossing it
// (critical damping). The hierarchy is solved once without walls; every joint whose planned
// acceleration crosses its wall becomes an equality row (q̈ = the wall) in a level above priority 1, and
// the hierarchy is solved again — an active set, at most kLimitPasses rounds per step. Where no wall is
// crossed the tasks are solved exactly as without walls.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "common/model.h"
#include "stages/simulate/prioritized_control.h"
#include "stages/simulate/task_references.h"

namespace syn {

struct ControllerOptions {
  // 1/s², the paper's controller code (task and posture gains). Ground mode, session 48, 8 rounding-level
  // runs of the 21 CMU walks onto G1 (17.00 up at these gains): the orientation tasks' feedback softened
  // about the vertical to 0.3 of it, about the horizontal axes to 0.5, or to 0.5 and 0.7: 15.88 / 16.50 /
  // 16.75 (the yaw and tilting moments they ask for are what no sole gives, but the walks fell sooner).
  double kp = 350.0;
  double kv = 25.0;   // 1/s, ditto
  // A walking leg straightens every step, and its foot's motion along the leg becomes a row nearly
  // given by the foot's other rows. Kept (cutoff 1e-6), the foot task alone has to bend the knee there,
  // which it can do only to second order, so the knee stays locked or is carried onto the mirrored
  // branch; dropped, the posture, which knows the reference knee angle, bends it. The same holds for an
  // arm swung back near its reach. 32 CMU trials (21 walks, 11 dances) retargeted onto G1, no effort
  // limits, walls as above (ω = 100), joint RMS within 3° of the kinematic motion
  // (`syn-simulate --no-effort-limits --independence-cutoff c` on each motion syn-retarget makes):
  //   c = 0.1: 20, 0.3: 29, 0.5, 0.6, 0.7, 0.8: 32 of 32. At 0.7 the walks are 0.09-0.48°, the dances
  //   up to 1.10° (94_07), priority-1 RMS 0.26-9 mm. With the URDF's effort limits: 17 of 32 (the walks
  //   15 of 21; 10_04 and 12_0x ask their 50 N·m waist for up to 300 N·m in their first frames).
  // The truncated eigen-decomposition this replaced (directions under 10 % of the largest eigenvalue
  // dropped) gave 31 of 32 (60_05 flipped an arm, 67°), walks up to 1.18°, with limits 16 of 32, at
  // 7.2× real time against 12-13× now.
  PrioritizedControlOptions hierarchy{.independence_cutoff = 0.7};
  // Clamp actuated torques to the URDF's joint effort (paper: the simulated robot's limits). Off is for
  // diagnosis: how much of a tracking error the limits cause.
  bool effort_limits = true;
  // Keep the branch joints inside the URDF's position limits by top-priority walls (see above). Off is
  // for diagnosis.
  bool joint_limits = true;
  // ω of the walls, rad/s. 100: a knee at 5 rad/s (a walk's swing) starts braking 0.05 rad before its
  // limit, with up to 10⁴ × that distance rad/s² — what a 1 kHz step resolves (ω h = 0.1).
  double limit_frequency = 100.0;
};

// Clamps each entry of tau to ±limit; returns how many it clamped.
int ClipToEffort(const Eigen::VectorXd& limit, Eigen::VectorXd& tau);

// A task's rows as bits: bit r for row r of a pose, 0-2 the angular rows and 3-5 the linear (ground frame);
// an orientation task has bits 0-2, a position task 3-5.
[[nodiscard]] constexpr unsigned TaskRowBits(TaskType type) {
  return type == TaskType::kPose ? 0x3fu : type == TaskType::kOrientation ? 0x07u : 0x38u;
}

class OperationalSpaceController {
 public:
  OperationalSpaceController(const Model& model, std::vector<ControlledTask> tasks, const ControllerOptions& options);

  // tau for the state `workspace` holds (setQ and setU done) tracking `references`, after saturation.
  // Returns the number of actuated entries that hit their effort limit.
  int calcTorques(Workspace& workspace, const std::vector<TaskReference>& references, const PostureReference& posture,
                  Eigen::VectorXd& tau);
  // After calcTorques: the forward dynamics udot = A⁻¹ (tau − b − g) at the same state, from the
  // factor and the bias forces that call computed (what Workspace::calcForwardDynamics gives, to
  // rounding, without two more passes over the tree).
  void calcAcceleration(const Eigen::VectorXd& tau, Eigen::VectorXd& udot) const;
  // Ground mode (BalanceController): a level above every task until cleared, the base's translational
  // rows of the equations of motion, A_b u̇ = base_force − (b + g)_b over `base_velocities`: the centre of
  // mass accelerates by the force the soles will push.
  void setCentreOfMassLevel(const std::vector<int>& base_velocities, const Eigen::VectorXd& base_force);
  void clearCentreOfMassLevel();
  // Ground mode (StanceFeet): a level above the centre of mass's, the standing feet held where they touched
  // down: jacobian u̇ = acceleration.
  void setStanceLevel(const Eigen::MatrixXd& jacobian, const Eigen::VectorXd& acceleration);
  void clearStanceLevel();
  // Ground mode: a level between the standing feet's and the centre of mass's, each swinging foot's heading
  // (its task's rotation about the vertical, what that task's PD asks of it), and a landing foot's position
  // too, kept exactly. At priority 1 a swinging foot's yaw row shares the hierarchy's independence cutoff
  // with the pelvis, hands and head, and was dropped in 60-65 % of the steps (CMU 02_01, 12_03 onto G1): a
  // leg straightening for its landing spun its hip yaw unopposed, and the foot landed turned (09_12: 45° off
  // the reference's heading, then the robot fell over a sole turned across its path; 03_03: 63°). Its
  // position rows fare no better (kept in 52-62 % of the steps). Kept exactly through the whole swing, they
  // made the leg's early, fast swing throw yaw moments no sole could take (12_02 fell in its first step in 12
  // of 16 rounding-level runs); its horizontal rows through its landing only (`landing`, the last 30 % of
  // the swing: SimulateOptions) do not, and the long walks go further. The height stays with the task: kept
  // exactly too, the feet came down harder (walks' peak vertical force p90 4.8 -> 5.3 body weights).
  // `feet`: the swinging feet's map tasks (pose or orientation; an orientation task has no position rows);
  // none clears the level. Held until the next call.
  struct SwingingFoot {
    size_t task;
    bool landing;
  };
  void setSwingingFeet(const std::vector<SwingingFoot>& feet);

  // After calcTorques: A and b + g at its state.
  const Eigen::MatrixXd& massMatrix() const { return mass_.mass(); }
  const Eigen::VectorXd& biasForces() const { return bias_forces_; }
  // After calcTorques: how many joint-limit walls the last call made active.
  int activeLimitCount() const { return static_cast<int>(active_limits_.size()); }

  // After calcTorques: which of task `task`'s rows the hierarchy kept, in TaskRowBits's layout. A dropped
  // row is nearly a combination of the rows kept before it (prioritized_control.h). A swinging foot's
  // rows count as kept where the swinging feet's level kept them (their copies at the task's own priority
  // then have nothing left to do and drop).
  unsigned keptTaskRows(size_t task) const;

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
  std::vector<PriorityLevel> levels_;  // walls, standing feet, swinging feet's headings, centre of mass, then the tasks' priorities
  std::vector<int> base_velocities_;
  Eigen::VectorXd base_force_;
  bool com_level_ = false;
  bool stance_level_ = false;
  // The swinging feet's level's rows: per row, its task and that task's row (TaskRowBits's layout).
  struct SwingingRow {
    size_t task;
    int row;
  };
  std::vector<SwingingRow> swinging_rows_;
  PrioritizedControl hierarchy_;
  TreeMassFactorization mass_;  // A at the step's configuration, factored once for every A⁻¹ x
  bool free_base_;
  Eigen::VectorXd effort_limit_;
  struct LimitedJoint {
    int q_index, u_index;
    double lower, upper;
  };
  struct ActiveLimit {
    int u_index;
    double acceleration;  // the wall's q̈
  };
  std::vector<LimitedJoint> limited_joints_;
  std::vector<ActiveLimit> active_limits_;
  Eigen::VectorXd planned_udot_;
  bool addViolatedWalls(Workspace& workspace, const Eigen::VectorXd& task_torques);
  void fillSwingingFeetLevel(int nu);
  std::vector<std::pair<int, int>> joint_q_u_;  // (q index, u index) of every 1-dof joint
  Eigen::Matrix<double, 6, Eigen::Dynamic> jacobian_;
  Eigen::VectorXd posture_acceleration_, bias_forces_, zero_;
  // Saturation: the entries inside their limits (free_) re-solved around the clipped joints.
  std::vector<int> free_;
  Eigen::VectorXd unclipped_, scratch_, wanted_udot_, clipped_udot_, column_, free_gap_, free_step_;
  Eigen::MatrixXd free_block_;
  void redistributeClippedTorque(Eigen::VectorXd& tau);
};

}  // namespace syn
