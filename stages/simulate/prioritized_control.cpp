#include "stages/simulate/prioritized_control.h"

#include <algorithm>
#include <cmath>
#include <numeric>

namespace syn {
namespace {

// A row whose Φ_ii is below this fraction of the level's largest is what the levels above already fix
// (e.g. G1's torso orientation under the head's: the head link is welded to the torso): rounding noise.
constexpr double kDroppedRow = 1e-10;

}  // namespace

void PrioritizedControl::invertKeptRows(SolvedLevel& solved, double independence_cutoff) const {
  // Pivoted Cholesky of Φ' in place, left-looking (as LAPACK's dpstf2): L in the lower triangle of the
  // first `rank` columns; a column of L is formed when its row is taken, from Φ' and the columns before
  // it, so only the remaining rows' Schur diagonal is updated each step. Rows and columns are swapped
  // whole, so the part not yet factored stays a symmetric permutation of Φ'.
  solved.unfactored = solved.operational;
  Eigen::MatrixXd& factor = solved.operational;
  const int rows = static_cast<int>(factor.rows());
  solved.kept_rows.resize(static_cast<size_t>(rows));
  std::iota(solved.kept_rows.begin(), solved.kept_rows.end(), 0);
  solved.schur_diagonal = factor.diagonal();
  int rank = 0;
  for (; rank < rows; ++rank) {
    int next = rank;
    for (int i = rank + 1; i < rows; ++i) {
      if (solved.schur_diagonal[i] > solved.schur_diagonal[next]) next = i;
    }
    if (!(solved.schur_diagonal[next] >= independence_cutoff)) break;
    if (next != rank) {
      factor.row(rank).swap(factor.row(next));
      factor.col(rank).swap(factor.col(next));
      std::swap(solved.schur_diagonal[rank], solved.schur_diagonal[next]);
      std::swap(solved.kept_rows[static_cast<size_t>(rank)], solved.kept_rows[static_cast<size_t>(next)]);
    }
    const double pivot = std::sqrt(solved.schur_diagonal[rank]);
    factor(rank, rank) = pivot;
    const int rest = rows - rank - 1;
    factor.col(rank).tail(rest).noalias() -= factor.bottomLeftCorner(rest, rank) * factor.row(rank).head(rank).transpose();
    factor.col(rank).tail(rest) /= pivot;
    solved.schur_diagonal.tail(rest) -= factor.col(rank).tail(rest).cwiseAbs2();
  }
  solved.rank = rank;
  solved.row_kept.assign(static_cast<size_t>(rows), 0);
  for (int k = 0; k < rank; ++k) solved.row_kept[static_cast<size_t>(solved.kept_rows[static_cast<size_t>(k)])] = 1;
  // Φ'_KK⁻¹ = L⁻ᵀ L⁻¹: L⁻¹ column by column (forward substitution from the column's own row: its
  // entries above are zero), then the lower triangle of the product, each entry a dot product of two
  // columns' tails. A sixth of m³ each, where solving L X = I and Lᵀ Y = X densely costs m³.
  const auto lower = factor.topLeftCorner(rank, rank);
  solved.factor_inverse.setZero(rank, rank);
  for (int b = 0; b < rank; ++b) {
    auto column = solved.factor_inverse.col(b);
    column[b] = 1.0;
    for (int c = b; c < rank; ++c) {
      column[c] /= lower(c, c);
      column.tail(rank - c - 1).noalias() -= lower.col(c).tail(rank - c - 1) * column[c];
    }
  }
  solved.kept_inverse.resize(rank, rank);
  for (int b = 0; b < rank; ++b) {
    for (int a = b; a < rank; ++a) {
      solved.kept_inverse(a, b) = solved.kept_inverse(b, a) =
          solved.factor_inverse.col(a).tail(rank - a).dot(solved.factor_inverse.col(b).tail(rank - a));
    }
  }
  // Λ = D Φ'⁻ D, scattered back from pivot order.
  solved.inertia.setZero(rows, rows);
  solved.kept_residual.resize(rank);
  for (int a = 0; a < rank; ++a) {
    const int row_a = solved.kept_rows[static_cast<size_t>(a)];
    solved.kept_residual[a] = solved.row_scale[row_a] * solved.residual[row_a];
    for (int b = 0; b < rank; ++b) {
      const int row_b = solved.kept_rows[static_cast<size_t>(b)];
      solved.inertia(row_a, row_b) = solved.row_scale[row_a] * solved.kept_inverse(a, b) * solved.row_scale[row_b];
    }
  }
  // F = D Φ'_KK (Φ'_KK² + μ²)⁻¹ D r = D (Φ'_KK + μ² Φ'_KK⁻¹)⁻¹ D r: one more small Cholesky.
  solved.kept_force.resize(rank);
  if (options_.damping > 0) {
    solved.damped.resize(rank, rank);
    for (int b = 0; b < rank; ++b) {
      for (int a = 0; a < rank; ++a) {
        solved.damped(a, b) = solved.unfactored(solved.kept_rows[static_cast<size_t>(a)], solved.kept_rows[static_cast<size_t>(b)]) +
                              options_.damping * options_.damping * solved.kept_inverse(a, b);
      }
    }
    solved.damped_factor.compute(solved.damped);
    solved.kept_force = solved.kept_residual;
    solved.damped_factor.solveInPlace(solved.kept_force);
  } else {
    solved.kept_force.noalias() = solved.kept_inverse * solved.kept_residual;
  }
  solved.force.setZero(rows);
  for (int a = 0; a < rank; ++a) {
    const int row_a = solved.kept_rows[static_cast<size_t>(a)];
    solved.force[row_a] = solved.row_scale[row_a] * solved.kept_force[a];
  }
}

bool PrioritizedControl::rowKept(size_t level, int row) const {
  const std::vector<char>& kept = solved_[level].row_kept;
  return row >= 0 && static_cast<size_t>(row) < kept.size() && kept[static_cast<size_t>(row)] != 0;
}

void PrioritizedControl::calcTorques(Workspace& workspace, const TreeMassFactorization& mass,
                                     const std::vector<PriorityLevel>& levels,
                                     const Eigen::VectorXd& posture_acceleration, Eigen::VectorXd& torques) {
  const int nu = workspace.model().nu();
  if (solved_.size() != levels.size()) solved_.resize(levels.size());
  udot_tasks_.setZero(nu);
  torques.setZero(nu);
  column_.resize(nu);
  product_.resize(nu);
  for (size_t k = 0; k < levels.size(); ++k) {
    const PriorityLevel& level = levels[k];
    SolvedLevel& solved = solved_[k];
    const Eigen::Index rows = level.jacobian.rows();
    if (rows == 0) {  // an empty level (no joint limit active): nothing to solve, no projection
      solved.projected.resize(0, nu);
      solved.j_minv.resize(0, nu);
      solved.inertia.resize(0, 0);
      solved.rank = 0;
      solved.row_kept.clear();
      continue;
    }
    // J_k| = J_k N_{<k} = J_k − Σ_j (J_k A⁻¹ J_j|ᵀ Λ_j) J_j|: the projectors of the levels above are
    // mutually A-orthogonal, so their product is this sum.
    solved.projected = level.jacobian;
    if (solved.couplings.size() != k) solved.couplings.resize(k), solved.weighted.resize(k);
    for (size_t j = 0; j < k; ++j) {
      const SolvedLevel& above = solved_[j];
      solved.couplings[j].resize(rows, above.inertia.cols());
      solved.weighted[j].resize(rows, above.inertia.cols());
      solved.couplings[j].noalias() = level.jacobian * above.j_minv.transpose();
      solved.weighted[j].noalias() = solved.couplings[j] * above.inertia;
      solved.projected.noalias() -= solved.weighted[j] * above.projected;
    }
    // J_k| A⁻¹ (the transpose of A⁻¹ J_k|ᵀ), by substitution with the factor, every row at once, and
    // Φ_k = J_k| A⁻¹ J_k|ᵀ with it. Λ_k = Φ_k⁻. Its rows mix units (1/kg for positions, 1/(kg m²) for a
    // light hand's rotation: diagonal entries from 0.3 to 10⁵ on G1), so factor the unit-diagonal
    // Φ' = D Φ D with D = diag(Φ)^(-1/2), whose pivots are fractions whatever the units, and Λ = D Φ'⁻ D
    // (the exact inverse when every row is kept; a symmetric reflexive generalized inverse otherwise,
    // which is what keeps the projectors exact). Rows the levels above leave no authority over
    // (Φ_ii ≈ 0) drop.
    solved.j_minv = solved.projected;
    mass.solveRowsInPlace(solved.j_minv, solved.operational);
    solved.row_scale.resize(rows);
    const double largest_diagonal = rows > 0 ? std::max(0.0, solved.operational.diagonal().maxCoeff()) : 0.0;
    for (Eigen::Index i = 0; i < rows; ++i) {
      const double diagonal = solved.operational(i, i);
      solved.row_scale[i] = diagonal > kDroppedRow * largest_diagonal && diagonal > 0 ? 1.0 / std::sqrt(diagonal) : 0.0;
    }
    solved.operational = solved.row_scale.asDiagonal() * solved.operational * solved.row_scale.asDiagonal();
    // F_k = Λ̃_k (ẍ*_k − J̇_k u − J_k A⁻¹ Γ_{<k}).
    solved.residual = level.acceleration;
    solved.residual.noalias() -= level.jacobian * udot_tasks_;
    invertKeptRows(solved, level.independence_cutoff >= 0 ? level.independence_cutoff : options_.independence_cutoff);
    udot_tasks_.noalias() += solved.j_minv.transpose() * solved.force;
    torques.noalias() += solved.projected.transpose() * solved.force;
  }
  // Γ_p = N_{<K+1}ᵀ A a_p, with Nᵀ x = x − Σ_j J_j|ᵀ Λ_j (A⁻¹ J_j|ᵀ)ᵀ x.
  workspace.calcMassTimes(posture_acceleration, product_);
  column_ = product_;
  for (SolvedLevel& solved : solved_) {
    solved.posture_residual.resize(solved.inertia.rows());
    solved.posture_force.resize(solved.inertia.rows());
    solved.posture_residual.noalias() = solved.j_minv * product_;
    solved.posture_force.noalias() = solved.inertia * solved.posture_residual;
    column_.noalias() -= solved.projected.transpose() * solved.posture_force;
  }
  torques += column_;
}

}  // namespace syn
