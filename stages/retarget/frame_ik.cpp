#include "stages/retarget/frame_ik.h"

#include <algorithm>
#include <cmath>

#include <ceres/ceres.h>

#include "common/configuration_space.h"
#include "common/tree_kinematics.h"
#include "stages/retarget/branch_joints.h"
#include "stages/retarget/speed_bound.h"

namespace syn {
namespace {

// After a bent retry that lost to the straight knee, the next kRetryRest frames whose targets are well out
// of reach (the previous task cost over kRetryRestCost × reachable_task_cost, a 32 mm residual: a scaled
// person, not a robot's own motion) keep the straight answer without trying: a walk whose legs the G1
// cannot stretch to (CMU 08_07) retried in 283 of its 302 frames and lost nearly every time, the retry half
// its IK time (whole stage 1,012 -> 1,515 frames/s; over the 32 CMU walks and dances onto G1 2,101 ->
// 2,487, P1 errors within 1.3 mm, the same contacts but for the deep squats of 94_07 and 94_15). Targets
// nearer reach retry every frame: resting from just over reachable_task_cost, a same-robot round trip's
// knee stayed straight two frames after a transient, 70° off (38° retrying).
constexpr int kRetryRest = 2;
constexpr double kRetryRestCost = 10.0;

// A joint's regularisation scale follows the cost of its own tasks (FrameIk::regularisationScales) but stays
// at least the whole frame's scale to this power: 1, as before, wherever the targets as a whole are out of
// reach (a scaled person), and a joint's own error decides only as the whole error vanishes (a robot's own
// motion). Over the 32 CMU walks and dances the power 4 leaves both robots' retargets within 0.2 mm (P1) of
// the whole-frame scale, and the power 2 too; on the same-robot jumping jack, power 2 lost a third of the gain.
constexpr double kWholeFrameScalePower = 4.0;

// FrameIk::solve's choice between a straight knee and the bent retry: with no previous frame the bent answer
// is kept unless the straight one costs 1 % less; mid-take the bent one must cost 10 % less, as a switch of
// branch is then followed by frames that cross between them only as fast as the motors allow.
constexpr double kBentKneePreference = 1.01;
constexpr double kMidTakeBranchSwitch = 0.9;
// rad/s or m/s: the fastest a base no motor drives (a virtual base chain) moves between frames: 0.5 rad a
// frame at 120 Hz, far from the ~π of a jump to the other Euler-angle solution, and far above a person's
// pelvis (under 10 rad/s in a dance). 20 rad/s held the HRP-4C's base back on CMU 94_07, whose right foot
// then stayed 0.5 m from its target for the rest of the take.
constexpr double kUnactuatedSpeed = 60.0;

// FrameIk::regularisationScale.
double ScaleForTaskCost(const FrameIkOptions& options, double task_cost) {
  if (options.reachable_task_cost <= 0) return 1.0;
  return std::clamp(std::sqrt(task_cost / options.reachable_task_cost), options.min_regularisation_scale, 1.0);
}

// Rotation vector of R_current R_targetᵀ: the world-frame rotation that takes
// the target orientation to the current one.
Eigen::Vector3d RotationError(const Eigen::Matrix3d& current, const Eigen::Quaterniond& target) {
  const Eigen::AngleAxisd difference(current * target.toRotationMatrix().transpose());
  return difference.angle() * difference.axis();
}


// The least-squares residual of one frame, evaluated at q = q0 ⊕ δ.
class TrackingCost final : public ceres::CostFunction {
 public:
  TrackingCost(const Model& model, const std::vector<IkTask>& tasks, const Eigen::VectorXd& q_reference,
               double posture_weight, double continuity_weight, double acceleration_weight)
      : model_(model),
        shape_(ConfigurationShape::Of(model.hasFreeBase(), model.nq())),
        tree_(model),
        tasks_(tasks),
        q_reference_(q_reference),
        posture_weight_(posture_weight),
        continuity_weight_(continuity_weight),
        acceleration_weight_(acceleration_weight),
        regularisation_scales_(Eigen::VectorXd::Ones(model.nu())),
        first_joint_u_(model.hasFreeBase() ? 6 : 0),
        q_offset_(model.hasFreeBase() ? 1 : 0),
        q0_(model.nq()),
        q_(model.nq()),
        jacobian_(6, model.nu()) {
    // Rows: 3 for a position, 3 for an orientation, 6 for a pose (position first), then one per joint.
    int rows = 0;
    for (const IkTask& task : tasks) {
      task_row_.push_back(rows);
      rows += task.type == TaskType::kPose ? 6 : 3;
    }
    regularisation_row_ = rows;
    set_num_residuals(rows + model.nu() - first_joint_u_);
    mutable_parameter_block_sizes()->push_back(model.nu());
  }

  // Joints the active set holds (FrameIk::Impl::held_mask, one entry per u; null: none): their Jacobian
  // columns are zero, so no Levenberg–Marquardt step moves them. Ceres's SubsetManifold did the same by
  // multiplying every Jacobian by its plus-Jacobian, a dense rows × nu × nu product per evaluation that was
  // a seventh of the stage's time on CMU dances.
  void setHeld(const std::vector<uint8_t>* held) { held_ = held; }

  // Per velocity, the factor on its posture, continuity and acceleration weights (FrameIk::regularisationScales),
  // set in place before each solve.
  Eigen::VectorXd& regularisationScales() { return regularisation_scales_; }

  // predicted_step: the step δ a constant velocity would take this frame (the acceleration term pulls
  // toward it), or nullptr for none (the first frame).
  void setFrame(const std::vector<IkTarget>* targets, const Eigen::VectorXd& q0, const Eigen::VectorXd* predicted_step = nullptr) {
    targets_ = targets;
    q0_ = q0;
    predicted_step_ = predicted_step;
  }

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const int nu = model_.nu();
    const Eigen::Map<const Eigen::VectorXd> delta(parameters[0], nu);
    Integrate(shape_, q0_.data(), delta.data(), q_.data());
    // Ceres evaluates an accepted point twice (cost, then Jacobian): place each configuration once. The
    // tree's own forward kinematics, not a Simbody state: Debian's Simbody checks the state on every
    // setQ, which was a fifth of the whole stage on CMU dances (tree_kinematics.h).
    if (!realized_ || q_ != realized_q_) {
      tree_.setQ(q_);
      realized_q_ = q_;
      realized_ = true;
    }
    Eigen::Map<Eigen::VectorXd> r(residuals, num_residuals());
    r.setZero();
    double* J = jacobians ? jacobians[0] : nullptr;
    if (J) Eigen::Map<Eigen::VectorXd>(J, static_cast<Eigen::Index>(num_residuals()) * nu).setZero();
    for (size_t i = 0; i < tasks_.size(); ++i) {
      const IkTask& task = tasks_[i];
      const IkTarget& target = (*targets_)[i];
      if (!target.active || task.weight == 0.0) continue;
      const int row = task_row_[i];
      const int orientation_row = task.type == TaskType::kPose ? row + 3 : row;
      const Eigen::Isometry3d& pose = tree_.linkPose(task.link);
      const bool use_position = task.type != TaskType::kOrientation;
      const bool use_orientation = task.type != TaskType::kPosition && target.has_orientation;
      if (use_position) r.segment<3>(row) = task.weight * (pose.translation() - target.position);
      Eigen::Vector3d rotation_error = Eigen::Vector3d::Zero();
      if (use_orientation) {
        rotation_error = RotationError(pose.linear(), target.orientation);
        r.segment<3>(orientation_row) = task.weight * rotation_error;
      }
      if (!J) continue;
      tree_.frameJacobian(task.link, jacobian_);
      Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> jacobian(J, num_residuals(), nu);
      // Frame Jacobian rows: angular velocity (0..2), then linear velocity of the link origin (3..5).
      if (use_position) jacobian.block(row, 0, 3, nu) = task.weight * jacobian_.bottomRows<3>();
      if (use_orientation) {
        jacobian.block(orientation_row, 0, 3, nu) = task.weight * RotationLeftJacobianInverse(rotation_error) * jacobian_.topRows<3>();
      }
    }
    // Three per-joint terms, all linear in δ on one coordinate, so they add up to one row each:
    //   posture       w_p (q0 + δ − q_ref)   toward the reference stance,
    //   velocity      w_v δ                  toward staying where the previous frame was,
    //   acceleration  w_a (δ − δ_predicted)  toward the previous frame's velocity.
    // The last two keep joints the tasks leave free (a wrist roll when only the hand's position is
    // known, a shoulder yaw under a hand pose) from chattering between equally good solutions; the
    // acceleration term does it without the lag a velocity term alone puts on a moving joint.
    // Σ w_i² (δ − t_i)² = w² (δ − δ*)² + const with w² = Σ w_i², δ* = Σ w_i² t_i / w².
    // The scale multiplies all three weights, so it leaves δ* alone and scales w.
    const int regularisation_row = regularisation_row_;
    const double posture2 = posture_weight_ * posture_weight_, velocity2 = continuity_weight_ * continuity_weight_;
    const double acceleration2 = predicted_step_ ? acceleration_weight_ * acceleration_weight_ : 0.0;
    const double combined2 = posture2 + velocity2 + acceleration2, combined = std::sqrt(combined2);
    for (int u = first_joint_u_; u < nu; ++u) {
      const int q_index = u + q_offset_;
      const double predicted = predicted_step_ ? (*predicted_step_)[u] : 0.0;
      const double target = (posture2 * (q_reference_[q_index] - q0_[q_index]) + acceleration2 * predicted) / combined2;
      const double weight = regularisation_scales_[u] * combined;
      r[regularisation_row + u - first_joint_u_] = weight * (delta[u] - target);
      if (J) J[static_cast<size_t>(regularisation_row + u - first_joint_u_) * nu + u] = weight;
    }
    if (J && held_) {
      for (int u = 0; u < nu; ++u) {
        if (!(*held_)[static_cast<size_t>(u)]) continue;
        for (int row = 0; row < num_residuals(); ++row) J[static_cast<size_t>(row) * nu + u] = 0.0;
      }
    }
    return true;
  }

 private:
  const Model& model_;
  const ConfigurationShape shape_;
  mutable TreeKinematics tree_;
  const std::vector<IkTask>& tasks_;
  const Eigen::VectorXd& q_reference_;
  double posture_weight_;
  double continuity_weight_;
  double acceleration_weight_;
  Eigen::VectorXd regularisation_scales_;
  const Eigen::VectorXd* predicted_step_ = nullptr;
  std::vector<int> task_row_;  // first residual row of each task
  int regularisation_row_ = 0;
  mutable Eigen::VectorXd realized_q_;
  mutable bool realized_ = false;
  int first_joint_u_;
  int q_offset_;
  const std::vector<IkTarget>* targets_ = nullptr;
  const std::vector<uint8_t>* held_ = nullptr;
  Eigen::VectorXd q0_;
  mutable Eigen::VectorXd q_;
  mutable Eigen::Matrix<double, 6, Eigen::Dynamic> jacobian_;
};

}  // namespace

struct FrameIk::Impl {
  const Model& model;
  std::vector<IkTask> tasks;
  Eigen::VectorXd q_reference;
  FrameIkOptions options;
  int first_joint = 0, q_offset = 0;
  Eigen::VectorXd delta;
  Eigen::VectorXd lower, upper;              // joint limits per u index (±inf for the base); branch joints >= 0
  std::vector<bool> branch;                  // [nq] branch_joints.h's coordinates
  bool has_branch_joints = false;
  // FrameIk::solve's branch retry: the frame's start, and the first answer while the second is tried.
  Eigen::VectorXd retry_q, retry_last_step, first_q, first_last_step;
  Eigen::VectorXd step_lower, step_upper;    // this frame's bounds on δ
  TrackingCost* cost = nullptr;              // owned by problem
  ceres::Problem problem;
  ceres::Solver::Options solver_options;
  TreeKinematics tree;  // measureErrors' forward kinematics
  // Active set: the joints held at a bound for this frame (TrackingCost::setHeld).
  std::vector<uint8_t> held_mask;
  Eigen::VectorXd last_step;       // the previous solve's δ
  Eigen::VectorXd predicted_step;  // this solve's constant-velocity prediction
  bool has_last_step = false;
  int retry_rest = 0;  // frames left before a straight knee's next bent retry (kRetryRest)
  // Per-joint regularisation (FrameIk::regularisationScales): which tasks each velocity moves ([nu × tasks],
  // 1 where the task's link is beyond the joint); the previous solve's cost per task (its taskCosts, valid
  // with has_last_step); scratch for the costs.
  Eigen::MatrixXd moves;
  Eigen::VectorXd last_task_costs, task_costs;
  Eigen::VectorXd residual, gradient;
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> jacobian;

  Impl(const Model& model_in, std::vector<IkTask> tasks_in, const Eigen::VectorXd& q_ref, double posture_weight,
       const FrameIkOptions& options_in)
      : model(model_in), tasks(std::move(tasks_in)), q_reference(q_ref), options(options_in),
        first_joint(model_in.hasFreeBase() ? 6 : 0), q_offset(model_in.hasFreeBase() ? 1 : 0),
        delta(Eigen::VectorXd::Zero(model_in.nu())), tree(model_in) {
    cost = new TrackingCost(model, tasks, q_reference, posture_weight, options.continuity_weight,
                            options.acceleration_weight);
    problem.AddResidualBlock(cost, nullptr, delta.data());
    lower = Eigen::VectorXd::Constant(model.nu(), -std::numeric_limits<double>::infinity());
    upper = Eigen::VectorXd::Constant(model.nu(), std::numeric_limits<double>::infinity());
    const Eigen::VectorXd retarget_lower = RetargetLowerLimits(model);
    for (int u = first_joint; u < model.nu(); ++u) {
      lower[u] = retarget_lower[u + q_offset];
      upper[u] = model.qUpper()[u + q_offset];
    }
    branch = BranchCoordinates(model);
    has_branch_joints = std::find(branch.begin(), branch.end(), true) != branch.end();
    step_lower = lower, step_upper = upper;
    // A joint moves a task's link when its Jacobian column for that link is not zero; which joints those are
    // depends only on the tree, so any configuration tells.
    moves = Eigen::MatrixXd::Zero(model.nu(), static_cast<Eigen::Index>(tasks.size()));
    tree.setQ(model.defaultQ());
    Eigen::Matrix<double, 6, Eigen::Dynamic> link_jacobian(6, model.nu());
    for (size_t i = 0; i < tasks.size(); ++i) {
      tree.frameJacobian(tasks[i].link, link_jacobian);
      for (int u = 0; u < model.nu(); ++u) moves(u, static_cast<Eigen::Index>(i)) = link_jacobian.col(u).norm() > 0 ? 1.0 : 0.0;
    }
    last_task_costs = task_costs = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(tasks.size()));
    held_mask.assign(static_cast<size_t>(model.nu()), 0);
    last_step = predicted_step = Eigen::VectorXd::Zero(model.nu());
    solver_options.max_num_iterations = options.max_iterations;
    solver_options.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
    solver_options.function_tolerance = options.function_tolerance;
    solver_options.gradient_tolerance = options.gradient_tolerance;
    solver_options.parameter_tolerance = options.parameter_tolerance;
    solver_options.logging_type = ceres::SILENT;
    solver_options.minimizer_progress_to_stdout = false;
    solver_options.num_threads = 1;
    // The unknowns are all radians or metres of similar size, so Jacobi scaling buys nothing here and
    // costs two passes over the Jacobian per iteration (same solutions, ~10 % of the solve time).
    solver_options.jacobi_scaling = false;
  }

  // ∇ ½‖r‖² with respect to δ at the current δ.
  const Eigen::VectorXd& costGradient() {
    const int rows = cost->num_residuals(), nu = model.nu();
    residual.resize(rows);
    jacobian.resize(rows, nu);
    const double* parameters[] = {delta.data()};
    double* jacobians[] = {jacobian.data()};
    cost->setHeld(nullptr);  // the whole gradient: a held joint's says whether to let it go
    cost->Evaluate(parameters, residual.data(), jacobians);
    cost->setHeld(&held_mask);
    gradient.noalias() = jacobian.transpose() * residual;
    return gradient;
  }

  // One step of the active-set method for the box lo ≤ δ ≤ hi: a free joint that left its box is put
  // back on the bound it crossed and held there; a held joint whose cost gradient points into the box is
  // let go. True when the held set changed (solve again).
  bool updateHeldJoints() {
    bool changed = false, any_held = false;
    for (int u = first_joint; u < model.nu(); ++u) {
      if (held_mask[u]) {
        any_held = true;
        continue;
      }
      if (delta[u] < step_lower[u] || delta[u] > step_upper[u]) {
        delta[u] = std::clamp(delta[u], step_lower[u], step_upper[u]);
        held_mask[u] = 1;
        changed = any_held = true;
      }
    }
    if (!changed && any_held) {
      // Release only when nothing new was clamped, so a release is judged at a point where the rest is solved.
      const Eigen::VectorXd& g = costGradient();
      for (int u = first_joint; u < model.nu(); ++u) {
        if (!held_mask[u]) continue;
        const bool inward = delta[u] <= step_lower[u] ? g[u] < 0 : g[u] > 0;
        if (inward) held_mask[u] = 0, changed = true;
      }
    }
    if (!changed) return false;
    applyHeldJoints();
    return true;
  }

  // Per velocity, the regularisation scale of the summed costs of the tasks it moves (kWholeFrameScalePower).
  void jointScales(const Eigen::VectorXd& costs, Eigen::VectorXd& out) const {
    out.noalias() = moves * costs;
    const double floor = std::pow(ScaleForTaskCost(options, costs.sum()), kWholeFrameScalePower);
    for (Eigen::Index u = 0; u < out.size(); ++u) out[u] = std::max(floor, ScaleForTaskCost(options, out[u]));
  }

  // Holds the joints held_mask marks (constant at their current δ: their Jacobian columns are zero).
  void applyHeldJoints() { cost->setHeld(&held_mask); }
};

FrameIk::FrameIk(const Model& model, std::vector<IkTask> tasks, const Eigen::VectorXd& q_reference,
                 double posture_weight, const FrameIkOptions& options)
    : impl_(std::make_unique<Impl>(model, std::move(tasks), q_reference, posture_weight, options)) {}

FrameIk::~FrameIk() = default;

FrameIkSummary FrameIk::solveOnce(const std::vector<IkTarget>& targets, Eigen::VectorXd& q, double step_time) {
  Impl& impl = *impl_;
  impl.delta.setZero();
  // Bounds are relative to the warm start; keep the start itself feasible.
  for (int u = impl.first_joint; u < impl.model.nu(); ++u) {
    const int q_index = u + impl.q_offset;
    q[q_index] = std::clamp(q[q_index], impl.lower[u], impl.upper[u]);
    double low = impl.lower[u] - q[q_index], high = impl.upper[u] - q[q_index];
    // A virtual base's URDF limits are placeholders (HRP-4C's floating_base_r1..r3: 1000 rad/s, 8.3 rad a
    // frame at 120 Hz): a box that wide let a frame of CMU 94_07 jump to the other Euler-angle solution for
    // the same pelvis orientation (r1 -0.14 -> 9.0 rad), after which r2 and r3 spun to ±8000 rad.
    const double speed = impl.model.actuatedVelocities()[static_cast<size_t>(u)]
                             ? SpeedPerScaledSecond(impl.model.uLimit()[u], impl.options.velocity_limit_scale)
                             : std::min(impl.model.uLimit()[u], kUnactuatedSpeed);
    const double reach = step_time * speed;
    if (step_time > 0 && std::isfinite(reach)) {
      low = std::max(low, -reach);
      high = std::min(high, reach);
    }
    impl.step_lower[u] = low, impl.step_upper[u] = high;
  }
  // The constant-velocity prediction (the previous frame's step, inside this frame's box) anchors the
  // acceleration term and is where the solver starts.
  const bool predict = impl.has_last_step && impl.options.acceleration_weight > 0;
  if (predict) {
    for (int u = 0; u < impl.model.nu(); ++u) {
      impl.predicted_step[u] = std::clamp(impl.last_step[u], impl.step_lower[u], impl.step_upper[u]);
    }
    impl.delta = impl.predicted_step;
  }
  impl.cost->setFrame(&targets, q, predict ? &impl.predicted_step : nullptr);
  // From the previous frame's answer: 1 on a take's first frame and after a gap.
  if (impl.has_last_step) {
    impl.jointScales(impl.last_task_costs, impl.cost->regularisationScales());
  } else {
    impl.cost->regularisationScales().setOnes();
  }
  // Joint limits (and the per-frame velocity bound) are a box on δ. Ceres's own bounds project each
  // Levenberg–Marquardt step onto the box and add a line search per step; when a joint presses on its
  // limit that crawls (tens of iterations for a fraction of the cost), because the step is computed as
  // if the joint could move. So the box is enforced by an active set around unconstrained solves: a
  // joint that would leave the box is held on its bound (its Jacobian column zero) and the others re-solved.
  // Joints that start on a bound and are pushed outward are held from the start.
  std::fill(impl.held_mask.begin(), impl.held_mask.end(), 0);
  bool start_on_bound = false;
  for (int u = impl.first_joint; u < impl.model.nu(); ++u) {
    start_on_bound = start_on_bound || impl.step_lower[u] >= 0 || impl.step_upper[u] <= 0;
  }
  if (start_on_bound) {
    const Eigen::VectorXd& g = impl.costGradient();
    for (int u = impl.first_joint; u < impl.model.nu(); ++u) {
      impl.held_mask[u] = (impl.step_lower[u] >= 0 && g[u] > 0) || (impl.step_upper[u] <= 0 && g[u] < 0);
      if (impl.held_mask[u]) impl.delta[u] = 0.0;  // the warm start is that bound
    }
  }
  impl.applyHeldJoints();

  FrameIkSummary result;
  ceres::Solver::Summary summary;
  constexpr int kMaxActiveSetRounds = 8;
  for (int round = 0; round < kMaxActiveSetRounds; ++round) {
    ceres::Solve(impl.solver_options, &impl.problem, &summary);
    if (round == 0) result.initial_cost = summary.initial_cost;
    result.iterations += static_cast<int>(summary.iterations.size()) - 1;  // iteration 0 only evaluates
    if (!impl.updateHeldJoints()) break;
  }
  // A last clamp: after the final round every free joint is inside the box up to rounding.
  for (int u = impl.first_joint; u < impl.model.nu(); ++u) {
    impl.delta[u] = std::clamp(impl.delta[u], impl.step_lower[u], impl.step_upper[u]);
  }
  impl.last_step = impl.delta;
  impl.has_last_step = true;
  Eigen::VectorXd solved(q.size());
  Integrate(ConfigurationShape::Of(impl.model.hasFreeBase(), impl.model.nq()), q, impl.delta, solved);
  q = solved;
  result.final_cost = summary.final_cost;
  result.converged = summary.termination_type == ceres::CONVERGENCE;
  return result;
}

// A knee that ends on its zero floor may have got there from the wrong side: a straight leg cannot tell
// +θ from −θ, so a leg straightening through the singularity is carried towards the mirrored solution and
// then held by the floor, bent the other way from its target (the same-robot round trip found G1 knees
// there, 25-80° off). Such a frame is solved again with its branch joints started at kBranchStart, and the
// answer kept by the costs (kBentKneePreference, kMidTakeBranchSwitch); a frame whose knees are off the floor
// is solved once. A scaled human's foot just beyond reach makes the straight leg a hair cheaper (0.7 % on
// CMU 07_01's first frame); taking it there leaves the next frames, whose bent answer is clearly cheaper,
// bending only as fast as the motors allow while the planted foot slides. (Not cured yet: on 07_01 the
// first frame's repeated solves, SolveFrames, still settle on a nearly straight knee off the floor, and the
// right sole slides 18 mm over the first 0.05 s.) A bent answer that meets the targets (task cost under
// reachable_task_cost) is kept whatever its joint terms cost: the acceleration such a switch takes
// otherwise held exact targets' knees straight for frames (the jumping jack's round trip: 10° off). Compared
// by the total cost alone (joint terms included), CMU 94_07 switched knees mid-squat and its P1 median
// went from 54 to 127 mm, so a scaled person's frames keep that rule.
FrameIkSummary FrameIk::solve(const std::vector<IkTarget>& targets, Eigen::VectorXd& q, double step_time) {
  FrameIkSummary summary = solveOnBranch(targets, q, step_time);
  taskCosts(targets, q, impl_->last_task_costs);
  return summary;
}

FrameIkSummary FrameIk::solveOnBranch(const std::vector<IkTarget>& targets, Eigen::VectorXd& q, double step_time) {
  Impl& impl = *impl_;
  if (!impl.has_branch_joints) return solveOnce(targets, q, step_time);
  impl.retry_q = q;
  impl.retry_last_step = impl.last_step;
  const bool had_last_step = impl.has_last_step;
  FrameIkSummary first = solveOnce(targets, q, step_time);
  bool on_floor = false;
  for (int u = impl.first_joint; u < impl.model.nu(); ++u) {
    on_floor = on_floor || (impl.branch[static_cast<size_t>(u + impl.q_offset)] && q[u + impl.q_offset] <= impl.lower[u] + 1e-6);
  }
  if (!on_floor) return first;
  if (had_last_step && impl.retry_rest > 0 && impl.last_task_costs.sum() > kRetryRestCost * impl.options.reachable_task_cost) {
    --impl.retry_rest;
    return first;
  }
  impl.first_q = q;
  impl.first_last_step = impl.last_step;
  q = impl.retry_q;
  impl.last_step = impl.retry_last_step;
  impl.has_last_step = had_last_step;
  BendBranchJoints(impl.branch, q);
  FrameIkSummary second = solveOnce(targets, q, step_time);
  const int iterations = first.iterations + second.iterations;
  const double preference = had_last_step ? kMidTakeBranchSwitch : kBentKneePreference;
  const double second_task_cost = taskCost(targets, q);
  const bool meets_targets = second_task_cost < impl.options.reachable_task_cost &&
                             second_task_cost < preference * taskCost(targets, impl.first_q);
  if (meets_targets || second.final_cost < preference * first.final_cost) {
    second.iterations = iterations;
    impl.retry_rest = 0;
    return second;
  }
  impl.retry_rest = kRetryRest;
  first.iterations = iterations;
  q = impl.first_q;
  impl.last_step = impl.first_last_step;
  return first;
}

void FrameIk::taskCosts(const std::vector<IkTarget>& targets, const Eigen::VectorXd& q, Eigen::VectorXd& costs) {
  Impl& impl = *impl_;
  impl.tree.setQ(q);
  costs.setZero(static_cast<Eigen::Index>(impl.tasks.size()));
  for (size_t i = 0; i < impl.tasks.size(); ++i) {
    if (!targets[i].active) continue;
    const IkTask& task = impl.tasks[i];
    const Eigen::Isometry3d& pose = impl.tree.linkPose(task.link);
    double squared = 0.0;
    if (task.type != TaskType::kOrientation) squared += (pose.translation() - targets[i].position).squaredNorm();
    if (task.type != TaskType::kPosition && targets[i].has_orientation) {
      squared += RotationError(pose.linear(), targets[i].orientation).squaredNorm();
    }
    costs[static_cast<Eigen::Index>(i)] = 0.5 * task.weight * task.weight * squared;
  }
}

double FrameIk::taskCost(const std::vector<IkTarget>& targets, const Eigen::VectorXd& q) {
  taskCosts(targets, q, impl_->task_costs);
  return impl_->task_costs.sum();
}

void FrameIk::regularisationScales(const std::vector<IkTarget>& targets, const Eigen::VectorXd& q, Eigen::VectorXd& scales) {
  taskCosts(targets, q, impl_->task_costs);
  impl_->jointScales(impl_->task_costs, scales);
}

double FrameIk::regularisationScale(double task_cost) const { return ScaleForTaskCost(impl_->options, task_cost); }

void FrameIk::forgetHistory() { impl_->has_last_step = false; }

void FrameIk::linearize(const std::vector<IkTarget>& targets, const Eigen::VectorXd& q, Eigen::VectorXd& residual,
                        Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>& jacobian) {
  Impl& impl = *impl_;
  const int rows = impl.cost->num_residuals(), nu = impl.model.nu();
  residual.resize(rows);
  jacobian.resize(rows, nu);
  impl.cost->setFrame(&targets, q);
  impl.cost->setHeld(nullptr);  // the whole linearisation, whatever the last solve held
  impl.delta.setZero();
  const double* parameters[] = {impl.delta.data()};
  double* jacobians[] = {jacobian.data()};
  impl.cost->Evaluate(parameters, residual.data(), jacobians);
}

void FrameIk::measureErrors(const std::vector<IkTarget>& targets, const Eigen::VectorXd& q,
                            std::vector<double>& position_error, std::vector<double>& angle_error) {
  Impl& impl = *impl_;
  impl.tree.setQ(q);
  position_error.assign(impl.tasks.size(), std::nan(""));
  angle_error.assign(impl.tasks.size(), std::nan(""));
  for (size_t i = 0; i < impl.tasks.size(); ++i) {
    if (!targets[i].active) continue;
    const Eigen::Isometry3d& pose = impl.tree.linkPose(impl.tasks[i].link);
    if (impl.tasks[i].type != TaskType::kOrientation) {
      position_error[i] = (pose.translation() - targets[i].position).norm();
    }
    if (impl.tasks[i].type != TaskType::kPosition && targets[i].has_orientation) {
      angle_error[i] = RotationError(pose.linear(), targets[i].orientation).norm();
    }
  }
}

}  // namespace syn
