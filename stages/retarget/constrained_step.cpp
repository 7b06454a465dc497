#include "stages/retarget/constrained_step.h"

#include <algorithm>
#include <cmath>

namespace syn {

ConstrainedStep::ConstrainedStep(int unknowns, int max_rows)
    : n_(unknowns),
      max_rows_(max_rows),
      a_(Eigen::MatrixXd::Zero(max_rows, unknowns)),
      a_active_(max_rows, unknowns),
      h_(unknowns, unknowns),
      h_inv_at_(unknowns, max_rows),
      s_(max_rows, max_rows),
      c_(Eigen::VectorXd::Zero(max_rows)),
      c_active_(max_rows),
      g_(unknowns),
      step0_(unknowns),
      mu_(max_rows),
      free_rhs_(unknowns),
      inequality_(static_cast<size_t>(max_rows), 0),
      active_(static_cast<size_t>(max_rows), 0),
      held_(static_cast<size_t>(unknowns), 0),
      held_value_(unknowns),
      h_factor_(unknowns),
      s_factor_(max_rows),
      jtj_(unknowns, unknowns),
      jtr_(unknowns) {}

double ConstrainedStep::solve(const RowMatrix* jacobian, const Eigen::VectorXd* residual, double damping,
                              const Eigen::VectorXd& lower, const Eigen::VectorXd& upper, Eigen::VectorXd& step) {
  jtj_.setZero();
  jtr_.setZero();
  if (jacobian) {
    jtj_.selfadjointView<Eigen::Lower>().rankUpdate(jacobian->transpose());
    jtj_.triangularView<Eigen::StrictlyUpper>() = jtj_.transpose();
    jtr_.noalias() = jacobian->transpose() * *residual;
  }
  jtj_.diagonal().array() += jacobian ? damping : 1.0;
  // Inequalities start active where they are violated now; no joint is held.
  for (int i = 0; i < max_rows_; ++i) active_[static_cast<size_t>(i)] = i < rows_ && (!inequality_[static_cast<size_t>(i)] || c_[i] < 0);
  std::fill(held_.begin(), held_.end(), 0);
  constexpr int kMaxRounds = 12;
  for (int round = 0; round < kMaxRounds; ++round) {
    solveWithActiveSet(step);
    bool changed = false;
    // Bounds first: a joint that leaves its box is held on the bound it crossed.
    for (int u = 0; u < n_; ++u) {
      if (held_[static_cast<size_t>(u)] || (step[u] >= lower[u] && step[u] <= upper[u])) continue;
      held_[static_cast<size_t>(u)] = 1;
      held_value_[u] = std::clamp(step[u], lower[u], upper[u]);
      changed = true;
    }
    if (changed) continue;
    // Then inequalities: a violated one joins, one whose multiplier pulls the point into the floor leaves.
    for (int i = 0; i < rows_; ++i) {
      if (!inequality_[static_cast<size_t>(i)]) continue;
      const double predicted = a_.row(i).dot(step) + c_[i];
      if (!active_[static_cast<size_t>(i)] && predicted < -1e-9) active_[static_cast<size_t>(i)] = 1, changed = true;
      else if (active_[static_cast<size_t>(i)] && mu_[i] > 1e-12) active_[static_cast<size_t>(i)] = 0, changed = true;
    }
    if (!changed) break;
  }
  double violation = 0;
  for (int i = 0; i < rows_; ++i) {
    const double predicted = a_.row(i).dot(step) + c_[i];
    violation = std::max(violation, inequality_[static_cast<size_t>(i)] ? -predicted : std::abs(predicted));
  }
  return violation;
}

void ConstrainedStep::solveWithActiveSet(Eigen::VectorXd& step) {
  // Held joints are moved by their fixed amount and taken out: their columns leave A and H.
  h_ = jtj_;
  g_ = jtr_;
  c_active_.setZero();
  a_active_.setZero();
  for (int i = 0; i < rows_; ++i) {
    if (!active_[static_cast<size_t>(i)]) continue;
    a_active_.row(i) = a_.row(i);
    c_active_[i] = c_[i];
  }
  for (int u = 0; u < n_; ++u) {
    if (!held_[static_cast<size_t>(u)]) continue;
    const double value = held_value_[u];
    g_.noalias() += h_.col(u) * value;
    c_active_.noalias() += a_active_.col(u) * value;
    a_active_.col(u).setZero();
  }
  for (int u = 0; u < n_; ++u) {
    if (!held_[static_cast<size_t>(u)]) continue;
    h_.row(u).setZero();
    h_.col(u).setZero();
    h_(u, u) = 1.0;
    g_[u] = 0.0;
  }
  h_factor_.compute(h_);
  step0_ = -g_;
  h_factor_.solveInPlace(step0_);
  h_inv_at_ = a_active_.transpose();
  h_factor_.solveInPlace(h_inv_at_);
  s_.noalias() = a_active_ * h_inv_at_;
  // Inactive rows: a unit diagonal, so their multiplier is 0. A tiny ridge keeps S definite when rows are
  // dependent (a foot planted while its leg is held on a limit): the step then meets them in least squares.
  for (int i = 0; i < max_rows_; ++i) s_(i, i) += active_[static_cast<size_t>(i)] && i < rows_ ? 1e-10 : 1.0;
  mu_.noalias() = a_active_ * step0_;
  mu_ += c_active_;
  s_factor_.compute(s_);
  s_factor_.solveInPlace(mu_);
  step.noalias() = step0_ - h_inv_at_ * mu_;
  for (int u = 0; u < n_; ++u) {
    if (held_[static_cast<size_t>(u)]) step[u] = held_value_[u];
  }
}

}  // namespace syn
