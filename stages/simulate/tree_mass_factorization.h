// A⁻¹ x for many x at one configuration, by Featherstone's sparse LTDL factorisation of the mass matrix
// (Rigid Body Dynamics Algorithms, §6.5): A = Lᵀ D L, where L is unit lower-triangular with non-zeros
// only where a velocity's column is an ancestor of its row in the kinematic tree. Factoring costs
// O(n d²) and each solve O(n d), d the tree's depth (G1: 35 velocities, depth ≤ 13), against Simbody's
// multiplyByMInv, which re-walks the articulated-body recursion for every vector.
//
// Why: the controller needs A⁻¹ Jᵀ for every task row (42 on G1) each 1 ms step. 42 multiplyByMInv calls
// took 74 µs of the step; calcM (composite-body inertias) plus this factorisation and 42 solves take
// about a fifth of that. Nothing is inverted: the factor is used by substitution.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "common/model.h"

namespace syn {

class TreeMassFactorization {
 public:
  explicit TreeMassFactorization(const Model& model);

  // Forms A at the workspace's configuration (setQ done) and factors it.
  void factor(Workspace& workspace);
  // x ← A⁻¹ x, in place (nu entries).
  void solveInPlace(Eigen::VectorXd& x) const;
  // x ← x A⁻¹ (every row of x, nu columns: A is symmetric): for a stack of Jacobian rows, J A⁻¹.
  void solveRowsInPlace(Eigen::MatrixXd& x) const;
  // The same, and gram ← x A⁻¹ xᵀ of the x given (symmetric, rows × rows): for a stack of task rows, J A⁻¹
  // and the task-space mobility J A⁻¹ Jᵀ. With A = Lᵀ D L, x A⁻¹ xᵀ = W Wᵀ where W = x L⁻¹ D^(-1/2), the
  // solve's half-way point: half the work of multiplying x by x A⁻¹, and symmetric to the last bit.
  void solveRowsInPlace(Eigen::MatrixXd& x, Eigen::MatrixXd& gram) const;

  // Parent velocity of each velocity in the tree (-1 at a root): within a multi-dof joint the previous
  // velocity, else the last velocity of the nearest moving ancestor joint.
  const std::vector<int>& parents() const { return parent_; }
  // A itself, as formed by the last factor().
  const Eigen::MatrixXd& mass() const { return mass_; }

 private:
  // x ← x L⁻¹ on every row of the column-major rows × nu array x (RBDA Table 6.4's back substitution,
  // from the leaves in), and x ← x L⁻ᵀ (the forward one, from the root out). A vector is one row.
  void solveRowsL(double* x, Eigen::Index rows) const;
  void solveRowsLTranspose(double* x, Eigen::Index rows) const;
  std::vector<int> parent_;
  // The ancestors of velocity k, nearest first, are ancestors_[ancestor_begin_[k] .. ancestor_begin_[k+1]):
  // the substitutions walk them per row stack without chasing parent_.
  std::vector<int> ancestors_, ancestor_begin_;
  Eigen::MatrixXd mass_;
  Eigen::MatrixXd factor_;  // D on the diagonal, L strictly below it (row k, ancestor column i)
  Eigen::VectorXd inverse_sqrt_d_;  // D^(-1/2)
};

}  // namespace syn
