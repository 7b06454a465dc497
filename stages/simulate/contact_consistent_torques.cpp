#include "stages/simulate/contact_consistent_torques.h"

#include <limits>

#include <Eigen/LU>

#include "stages/simulate/operational_space_controller.h"

namespace syn {

ContactConsistentTorques::ContactConsistentTorques(const Model& model, const std::vector<RobotFoot>& feet,
                                                   const ContactForceOptions& options, bool effort_limits,
                                                   const ContactConsistentOptions& consistent)
    : split_(model, feet, options), options_(consistent), effort_limit_(model.effortLimit()) {
  if (!effort_limits) effort_limit_.setConstant(std::numeric_limits<double>::infinity());
  for (size_t f = 0; f < feet.size(); ++f) {
    foot_links_.push_back(model.findLinkIndex(feet[f].link));
    for (const std::array<double, 3>& local : feet[f].sole_points) {
      point_foot_.push_back(static_cast<int>(f));
      point_local_.emplace_back(local[0], local[1], local[2]);
    }
  }
  for (int i = 0; i < model.nu(); ++i) {
    if (!model.actuatedVelocities()[static_cast<size_t>(i)]) unactuated_.push_back(i);
  }
  fit_row_weights_ << Eigen::Vector3d::Constant(consistent.moment_weight), Eigen::Vector3d::Ones();
  const int nu = model.nu();
  jacobian_.resize(6, nu);
  hessian_.resize(nu, nu);
  base_rows_.resize(6, nu);
  wrench_rows_.resize(6, nu);
  response_.resize(nu, 6);
}

int ContactConsistentTorques::apply(Workspace& workspace, const Eigen::MatrixXd& mass, const Eigen::VectorXd& bias,
                                    const Eigen::VectorXd& planned_udot, const int64_t* planted,
                                    const Eigen::MatrixXd& stance_jacobian, const Eigen::VectorXd& stance_acceleration,
                                    Eigen::VectorXd& tau) {
  // Nearest the plan without the base's rows: H u̇ = A u̇* + w J_sᵀ a_s.
  hessian_ = mass;
  gradient_.noalias() = mass * planned_udot;
  if (stance_jacobian.rows() > 0) {
    hessian_.noalias() += options_.stance_weight * (stance_jacobian.transpose() * stance_jacobian);
    gradient_.noalias() += options_.stance_weight * (stance_jacobian.transpose() * stance_acceleration);
  }
  hessian_solver_.compute(hessian_);
  free_udot_ = hessian_solver_.solve(gradient_);
  // The base's rows as the wrench they need about the centre of mass: W(u̇) = X (A_b u̇ + (b + g)_b).
  const Eigen::Matrix<double, 6, 6> to_wrench = split_.wrenchFromBaseForces(workspace);
  Eigen::Matrix<double, 6, 1> base_bias;
  for (Eigen::Index r = 0; r < 6; ++r) {
    const int i = unactuated_[static_cast<size_t>(r)];
    base_rows_.row(r) = mass.row(i);
    base_bias[r] = bias[i];
  }
  wrench_rows_.noalias() = to_wrench * base_rows_;
  const Eigen::Matrix<double, 6, 1> wanted = wrench_rows_ * free_udot_ + to_wrench * base_bias;
  split_.fit(workspace, workspace.getU(), wanted, planted, planned_, fit_row_weights_);
  // The constrained minimum: u̇ = u̇_free + H⁻¹ Pᵀ (P H⁻¹ Pᵀ)⁻¹ (w − W(u̇_free)), w the fitted wrench.
  response_ = hessian_solver_.solve(wrench_rows_.transpose());
  const Eigen::Matrix<double, 6, 6> compliance = wrench_rows_ * response_;
  udot_ = free_udot_;
  udot_.noalias() -= response_ * compliance.partialPivLu().solve(planned_.unexplained);
  sole_forces_.setZero(tau.size());
  for (size_t p = 0; p < point_local_.size(); ++p) {
    const Eigen::Vector3d& force = planned_.point_force[p];
    if (force.isZero()) continue;
    workspace.calcFrameJacobian(foot_links_[static_cast<size_t>(point_foot_[p])], point_local_[p], jacobian_);
    sole_forces_.noalias() += jacobian_.bottomRows<3>().transpose() * force;
  }
  tau.noalias() = mass * udot_;
  tau += bias - sole_forces_;
  for (int i : unactuated_) tau[i] = 0.0;
  return ClipToEffort(effort_limit_, tau);
}

}  // namespace syn
