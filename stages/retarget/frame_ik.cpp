#include "stages/retarget/frame_ik.h"

#include <cmath>

#include <ceres/ceres.h>

namespace syn {
namespace {

constexpr int kRowsPerTask = 6;  // position (3) then orientation (3); unused rows stay zero

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
               double posture_weight, double continuity_weight)
      : model_(model),
        workspace_(model),
        tasks_(tasks),
        q_reference_(q_reference),
        posture_weight_(posture_weight),
        continuity_weight_(continuity_weight),
        first_joint_u_(model.hasFreeBase() ? 6 : 0),
        q_offset_(model.hasFreeBase() ? 1 : 0),
        q0_(model.nq()),
        q_(model.nq()),
        jacobian_(6, model.nu()) {
    set_num_residuals(static_cast<int>(tasks.size()) * kRowsPerTask + 2 * (model.nu() - first_joint_u_));
    mutable_parameter_block_sizes()->push_back(model.nu());
  }

  void setFrame(const std::vector<IkTarget>* targets, const Eigen::VectorXd& q0) {
    targets_ = targets;
    q0_ = q0;
  }

  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const int nu = model_.nu();
    const Eigen::Map<const Eigen::VectorXd> delta(parameters[0], nu);
    ApplyVelocityStep(model_, q0_, delta, q_);
    workspace_.setQ(q_);
    Eigen::Map<Eigen::VectorXd> r(residuals, num_residuals());
    r.setZero();
    double* J = jacobians ? jacobians[0] : nullptr;
    if (J) Eigen::Map<Eigen::VectorXd>(J, static_cast<Eigen::Index>(num_residuals()) * nu).setZero();
    for (size_t i = 0; i < tasks_.size(); ++i) {
      const IkTask& task = tasks_[i];
      const IkTarget& target = (*targets_)[i];
      if (!target.active || task.weight == 0.0) continue;
      const int row = static_cast<int>(i) * kRowsPerTask;
      const Eigen::Isometry3d pose = workspace_.findLinkPose(task.link);
      const bool use_position = task.type != TaskType::kOrientation;
      const bool use_orientation = task.type != TaskType::kPosition && target.has_orientation;
      if (use_position) r.segment<3>(row) = task.weight * (pose.translation() - target.position);
      if (use_orientation) r.segment<3>(row + 3) = task.weight * RotationError(pose.linear(), target.orientation);
      if (!J) continue;
      workspace_.calcFrameJacobian(task.link, Eigen::Vector3d::Zero(), jacobian_);
      Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>> jacobian(J, num_residuals(), nu);
      // Frame Jacobian rows: angular velocity (0..2), then linear velocity of the link origin (3..5).
      // d log(R R*ᵀ) ≈ ω for the small steps of one frame.
      if (use_position) jacobian.block(row, 0, 3, nu) = task.weight * jacobian_.bottomRows<3>();
      if (use_orientation) jacobian.block(row + 3, 0, 3, nu) = task.weight * jacobian_.topRows<3>();
    }
    const int posture_row = static_cast<int>(tasks_.size()) * kRowsPerTask;
    for (int u = first_joint_u_; u < nu; ++u) {
      const int q_index = u + q_offset_;
      r[posture_row + u - first_joint_u_] = posture_weight_ * (q_[q_index] - q_reference_[q_index]);
      if (J) J[static_cast<size_t>(posture_row + u - first_joint_u_) * nu + u] = posture_weight_;
    }
    // Continuity: joints the tasks leave free (a wrist roll when only the hand's position is known) stay
    // where the previous frame had them instead of wandering to wherever the posture term is flattest.
    const int continuity_row = posture_row + nu - first_joint_u_;
    for (int u = first_joint_u_; u < nu; ++u) {
      r[continuity_row + u - first_joint_u_] = continuity_weight_ * delta[u];
      if (J) J[static_cast<size_t>(continuity_row + u - first_joint_u_) * nu + u] = continuity_weight_;
    }
    return true;
  }

 private:
  const Model& model_;
  mutable Workspace workspace_;
  const std::vector<IkTask>& tasks_;
  const Eigen::VectorXd& q_reference_;
  double posture_weight_;
  double continuity_weight_;
  int first_joint_u_;
  int q_offset_;
  const std::vector<IkTarget>* targets_ = nullptr;
  Eigen::VectorXd q0_;
  mutable Eigen::VectorXd q_;
  mutable Eigen::Matrix<double, 6, Eigen::Dynamic> jacobian_;
};

}  // namespace

void ApplyVelocityStep(const Model& model, const Eigen::VectorXd& q0, const Eigen::VectorXd& delta, Eigen::VectorXd& q) {
  q = q0;
  if (!model.hasFreeBase()) {
    q += delta;
    return;
  }
  const Eigen::Vector3d rotation = delta.head<3>();
  const double angle = rotation.norm();
  const Eigen::Quaterniond step =
      angle > 0 ? Eigen::Quaterniond(Eigen::AngleAxisd(angle, rotation / angle)) : Eigen::Quaterniond::Identity();
  const Eigen::Quaterniond base = (step * Eigen::Quaterniond(q0[0], q0[1], q0[2], q0[3])).normalized();
  q[0] = base.w(), q[1] = base.x(), q[2] = base.y(), q[3] = base.z();
  q.segment<3>(4) += delta.segment<3>(3);
  q.tail(q.size() - 7) += delta.tail(delta.size() - 6);
}

struct FrameIk::Impl {
  const Model& model;
  std::vector<IkTask> tasks;
  Eigen::VectorXd q_reference;
  FrameIkOptions options;
  Eigen::VectorXd delta;
  Eigen::VectorXd lower, upper;  // joint limits per u index (±inf for the base)
  TrackingCost* cost = nullptr;  // owned by problem
  ceres::Problem problem;
  ceres::Solver::Options solver_options;
  Workspace workspace;

  Impl(const Model& model_in, std::vector<IkTask> tasks_in, const Eigen::VectorXd& q_ref, double posture_weight,
       const FrameIkOptions& options_in)
      : model(model_in), tasks(std::move(tasks_in)), q_reference(q_ref), options(options_in),
        delta(Eigen::VectorXd::Zero(model_in.nu())), workspace(model_in) {
    cost = new TrackingCost(model, tasks, q_reference, posture_weight, options.continuity_weight);
    problem.AddResidualBlock(cost, nullptr, delta.data());
    const int offset = model.hasFreeBase() ? 1 : 0;
    const int first_joint = model.hasFreeBase() ? 6 : 0;
    lower = Eigen::VectorXd::Constant(model.nu(), -std::numeric_limits<double>::infinity());
    upper = Eigen::VectorXd::Constant(model.nu(), std::numeric_limits<double>::infinity());
    for (int u = first_joint; u < model.nu(); ++u) {
      lower[u] = model.qLower()[u + offset];
      upper[u] = model.qUpper()[u + offset];
    }
    solver_options.linear_solver_type = ceres::DENSE_NORMAL_CHOLESKY;
    solver_options.max_num_iterations = options.max_iterations;
    solver_options.function_tolerance = options.function_tolerance;
    solver_options.gradient_tolerance = options.gradient_tolerance;
    solver_options.parameter_tolerance = options.parameter_tolerance;
    solver_options.logging_type = ceres::SILENT;
    solver_options.minimizer_progress_to_stdout = false;
    solver_options.num_threads = 1;
  }
};

FrameIk::FrameIk(const Model& model, std::vector<IkTask> tasks, const Eigen::VectorXd& q_reference,
                 double posture_weight, const FrameIkOptions& options)
    : impl_(std::make_unique<Impl>(model, std::move(tasks), q_reference, posture_weight, options)) {}

FrameIk::~FrameIk() = default;

FrameIkSummary FrameIk::solve(const std::vector<IkTarget>& targets, Eigen::VectorXd& q, double step_time) {
  Impl& impl = *impl_;
  const int offset = impl.model.hasFreeBase() ? 1 : 0;
  const int first_joint = impl.model.hasFreeBase() ? 6 : 0;
  impl.delta.setZero();
  // Bounds are relative to the warm start; keep the start itself feasible.
  for (int u = first_joint; u < impl.model.nu(); ++u) {
    const double value = q[u + offset];
    q[u + offset] = std::min(std::max(value, impl.lower[u]), impl.upper[u]);
    double low = impl.lower[u] - q[u + offset], high = impl.upper[u] - q[u + offset];
    const double reach = step_time * impl.model.uLimit()[u];
    if (step_time > 0 && std::isfinite(reach)) {
      low = std::max(low, -reach);
      high = std::min(high, reach);
    }
    // Ceres keeps bounds between solves: reset them every frame (±max() stands for none).
    impl.problem.SetParameterLowerBound(impl.delta.data(), u, std::isfinite(low) ? low : -std::numeric_limits<double>::max());
    impl.problem.SetParameterUpperBound(impl.delta.data(), u, std::isfinite(high) ? high : std::numeric_limits<double>::max());
  }
  impl.cost->setFrame(&targets, q);
  ceres::Solver::Summary summary;
  ceres::Solve(impl.solver_options, &impl.problem, &summary);
  Eigen::VectorXd solved(q.size());
  ApplyVelocityStep(impl.model, q, impl.delta, solved);
  q = solved;
  FrameIkSummary result;
  result.iterations = static_cast<int>(summary.iterations.size());
  result.initial_cost = summary.initial_cost;
  result.final_cost = summary.final_cost;
  result.converged = summary.termination_type == ceres::CONVERGENCE;
  return result;
}

void FrameIk::linearize(const std::vector<IkTarget>& targets, const Eigen::VectorXd& q, Eigen::VectorXd& residual,
                        Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>& jacobian) {
  Impl& impl = *impl_;
  const int rows = impl.cost->num_residuals(), nu = impl.model.nu();
  residual.resize(rows);
  jacobian.resize(rows, nu);
  impl.cost->setFrame(&targets, q);
  impl.delta.setZero();
  const double* parameters[] = {impl.delta.data()};
  double* jacobians[] = {jacobian.data()};
  impl.cost->Evaluate(parameters, residual.data(), jacobians);
}

void FrameIk::measureErrors(const std::vector<IkTarget>& targets, const Eigen::VectorXd& q,
                            std::vector<double>& position_error, std::vector<double>& angle_error) {
  Impl& impl = *impl_;
  impl.workspace.setQ(q);
  position_error.assign(impl.tasks.size(), std::nan(""));
  angle_error.assign(impl.tasks.size(), std::nan(""));
  for (size_t i = 0; i < impl.tasks.size(); ++i) {
    if (!targets[i].active) continue;
    const Eigen::Isometry3d pose = impl.workspace.findLinkPose(impl.tasks[i].link);
    if (impl.tasks[i].type != TaskType::kOrientation) {
      position_error[i] = (pose.translation() - targets[i].position).norm();
    }
    if (impl.tasks[i].type != TaskType::kPosition && targets[i].has_orientation) {
      angle_error[i] = RotationError(pose.linear(), targets[i].orientation).norm();
    }
  }
}

}  // namespace syn
