#include "stages/simulate/contact_consistent_torques.h"

#include <limits>

namespace syn {

ContactConsistentTorques::ContactConsistentTorques(const Model& model, const std::vector<RobotFoot>& feet,
                                                   const ContactForceOptions& options, bool effort_limits)
    : split_(model, feet, options), effort_limit_(model.effortLimit()) {
  if (!effort_limits) effort_limit_.setConstant(std::numeric_limits<double>::infinity());
  for (size_t f = 0; f < feet.size(); ++f) {
    foot_links_.push_back(model.findLinkIndex(feet[f].link));
    for (const std::array<double, 3>& local : feet[f].sole_points) {
      point_foot_.push_back(static_cast<int>(f));
      point_local_.emplace_back(local[0], local[1], local[2]);
    }
  }
  for (int i = 0; i < model.nu(); ++i) {
    (model.actuatedVelocities()[static_cast<size_t>(i)] ? actuated_ : unactuated_).push_back(i);
  }
  jacobian_.resize(6, model.nu());
}

int ContactConsistentTorques::apply(Workspace& workspace, const OperationalSpaceController& controller,
                                    const int64_t* planted, Eigen::VectorXd& tau) {
  controller.calcAcceleration(tau, planned_udot_);
  split_.split(workspace, workspace.getU(), tau, planted, planned_);
  sole_forces_.setZero(tau.size());
  for (size_t p = 0; p < point_local_.size(); ++p) {
    const Eigen::Vector3d& force = planned_.point_force[p];
    if (force.isZero()) continue;
    workspace.calcFrameJacobian(foot_links_[static_cast<size_t>(point_foot_[p])], point_local_[p], jacobian_);
    sole_forces_.noalias() += jacobian_.bottomRows<3>().transpose() * force;
  }
  const Eigen::MatrixXd& mass = controller.massMatrix();
  const Eigen::VectorXd& bias = controller.biasForces();
  const Eigen::Index base = static_cast<Eigen::Index>(unactuated_.size());
  base_block_.resize(base, base);
  base_rhs_.resize(base);
  for (Eigen::Index r = 0; r < base; ++r) {
    const int i = unactuated_[static_cast<size_t>(r)];
    base_rhs_[r] = sole_forces_[i] - bias[i];
    for (int j : actuated_) base_rhs_[r] -= mass(i, j) * planned_udot_[j];
    for (Eigen::Index c = 0; c < base; ++c) base_block_(r, c) = mass(i, unactuated_[static_cast<size_t>(c)]);
  }
  base_solver_.compute(base_block_);
  base_rhs_ = base_solver_.solve(base_rhs_);
  for (Eigen::Index r = 0; r < base; ++r) planned_udot_[unactuated_[static_cast<size_t>(r)]] = base_rhs_[r];
  tau.noalias() = mass * planned_udot_;
  tau += bias - sole_forces_;
  for (int i : unactuated_) tau[i] = 0.0;
  return ClipToEffort(effort_limit_, tau);
}

}  // namespace syn
