#include "stages/simulate/prioritized_control.h"

#include <algorithm>
#include <cmath>

namespace syn {
namespace {

// A row whose Φ_ii is below this fraction of the level's largest is what the levels above already fix
// (e.g. G1's torso orientation under the head's: the head link is welded to the torso): rounding noise.
constexpr double kDroppedRow = 1e-10;

}  // namespace

void PrioritizedControl::invertByEigenvectors(SolvedLevel& solved) const {
  // Λ_k = D Φ'⁺ D with the directions under the cutoff dropped, and F_k with each kept eigenvalue's
  // inverse damped to λ/(λ² + μ²).
  const Eigen::Index rows = solved.operational.rows();
  solved.eigen.compute(solved.operational);
  const Eigen::VectorXd& eigenvalues = solved.eigen.eigenvalues();
  const double largest = rows > 0 ? std::max(0.0, eigenvalues.maxCoeff()) : 0.0;
  solved.inverse_eigenvalues.resize(rows);
  solved.damped_inverse_eigenvalues.resize(rows);
  solved.rank = 0;
  const double damping_sq = options_.damping * options_.damping;
  for (Eigen::Index i = 0; i < rows; ++i) {
    const double eigenvalue = eigenvalues[i];
    const bool kept = largest > 0 && eigenvalue > options_.singular_cutoff * largest;
    solved.inverse_eigenvalues[i] = kept ? 1.0 / eigenvalue : 0.0;
    solved.damped_inverse_eigenvalues[i] = kept ? eigenvalue / (eigenvalue * eigenvalue + damping_sq) : 0.0;
    solved.rank += kept ? 1 : 0;
  }
  const Eigen::MatrixXd& vectors = solved.eigen.eigenvectors();
  solved.scaled.resize(rows, rows);
  solved.scaled.noalias() = solved.row_scale.asDiagonal() * vectors * solved.inverse_eigenvalues.asDiagonal();
  solved.inertia.resize(rows, rows);
  solved.inertia.noalias() = solved.scaled * (solved.row_scale.asDiagonal() * vectors).transpose();
  // F = D V diag(damped) Vᵀ D r, by matrix-vector products.
  solved.scaled_residual.noalias() = vectors.transpose() * solved.row_scale.cwiseProduct(solved.residual);
  solved.term = solved.damped_inverse_eigenvalues.cwiseProduct(solved.scaled_residual);
  solved.force.noalias() = vectors * solved.term;
  solved.force = solved.row_scale.cwiseProduct(solved.force);
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
    // J_k| A⁻¹ (the transpose of A⁻¹ J_k|ᵀ), by substitution with the factor, every row at once.
    solved.j_minv = solved.projected;
    mass.solveRowsInPlace(solved.j_minv);
    // Λ_k = (J_k| A⁻¹ J_k|ᵀ)⁺. Its rows mix units (1/kg for positions, 1/(kg m²) for a light hand's
    // rotation: eigenvalues from 0.3 to 10⁵ on G1), so decompose the unit-diagonal Φ' = D Φ D with
    // D = diag(Φ)^(-1/2), whose eigenvalues lie in [0, m_k] whatever the units, and Λ = D Φ'⁺ D (the
    // exact inverse when Φ is regular; a symmetric reflexive generalized inverse otherwise, which is
    // what keeps the projectors exact). Rows the levels above leave no authority over (Φ_ii ≈ 0) drop.
    solved.operational.resize(rows, rows);
    solved.operational.noalias() = solved.projected * solved.j_minv.transpose();
    solved.operational = 0.5 * (solved.operational + solved.operational.transpose()).eval();
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
    solved.force.resize(rows);
    invertByEigenvectors(solved);
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
