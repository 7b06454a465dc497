// Strict task priorities by dynamically consistent null-space projection (Khatib 1987; Sentis & Khatib
// 2005), the controller of the paper's dynamic mapping.
//
// Levels k = 1..K, each a stack of task rows: J_k (m_k × nu) and the wanted task acceleration
// ẍ*_k (m_k). With A the mass matrix and N_{<k} the projector of every level above k:
//
//   J_k|  = J_k N_{<k}                      (the level restricted to what the levels above leave free)
//   Λ_k   = (J_k| A⁻¹ J_k|ᵀ)⁻                (task-space inertia, m_k × m_k: the inverse over the rows a
//                                            pivoted Cholesky keeps, zero on the nearly dependent rows)
//   J̄_k   = A⁻¹ J_k|ᵀ Λ_k                    (dynamically consistent generalized inverse)
//   F_k   = Λ̃_k (ẍ*_k − J̇_k u − J_k A⁻¹ Γ_{<k})   (Γ_{<k}: the task torques of the levels above; Λ̃_k
//           the damped inverse, λ/(λ² + μ²) per eigen-direction of the kept rows' Φ')
//   Γ_k   = J_k|ᵀ F_k,      N_{<k+1} = N_{<k} − J̄_k J_k|
//
// and after the last level the joint-space posture acceleration a_p enters as Γ_p = N_{<K+1}ᵀ A a_p,
// i.e. the part of a_p that leaves every task's acceleration alone. Γ = Σ Γ_k + Γ_p; the caller adds
// gravity and Coriolis compensation. The projectors use the undamped Λ_k, so a lower level's torque
// never changes a higher level's acceleration along the rows it keeps (Λ_k is a symmetric reflexive
// generalized inverse, Λ Φ Λ = Λ, whichever rows are kept): level 1 tracks exactly as if level 2 did
// not exist. A dropped row is nearly a combination of kept ones, so it is still tracked through them
// as far as they agree with it; what they do not fix of it passes to the levels below.
//
// Which rows: a pivoted Cholesky of the unit-diagonal Φ' (rank-revealing, as in Higham's "Cholesky
// factorization" §10.3) takes the row with the largest remaining pivot first; a pivot is the share of
// that row's task-space mobility (in the A⁻¹ metric) that the rows taken before it do not already
// give, so rows stop being taken when the largest left is under `independence_cutoff`. This replaced
// a truncated eigen-decomposition of Φ', which dropped eigen-directions under a fraction of the
// largest: the same tracking on the CMU walks, but the 33 × 33 eigen-decomposition was 55 % of a
// G1 step, the Cholesky is an eighth of it (see ControllerOptions for the numbers).
//
// Cost per call: Σ m_k products A⁻¹ x (substitutions with the caller's sparse factor of A, O(nu · depth)
// each, Φ_k from their half-way point) and one A x; A is never inverted. Only the m_k × m_k matrices are
// dense: the pivoted Cholesky, Φ'_KK⁻¹ from its triangular factor (m³/3), and the damped inverse's
// Cholesky. Session 38 made these three and Φ_k's product symmetric-only: 12.5× → 14.3× real time in
// paper mode on the 21 CMU walks. No allocation after the first call with a given level layout.
#pragma once

#include <vector>

#include <Eigen/Core>
#include <Eigen/Cholesky>

#include "common/model.h"
#include "stages/simulate/tree_mass_factorization.h"

namespace syn {

struct PriorityLevel {
  Eigen::MatrixXd jacobian;       // J_k [m_k, nu]
  Eigen::VectorXd acceleration;   // ẍ*_k − J̇_k u [m_k]: the wanted task acceleration minus the velocity term
  // This level's own independence cutoff (PrioritizedControlOptions); negative: the options'.
  double independence_cutoff = -1;
};

struct PrioritizedControlOptions {
  // A row of the unit-diagonal Φ' = D J_k| A⁻¹ J_k|ᵀ D (see the .cpp) is kept while its pivot, the
  // fraction of its mobility independent of the rows kept before it, is at least this: a limb at a
  // singularity (a straight knee: the foot's motion along the leg) then gets no force there instead of
  // an unbounded one, and the row passes to the levels below. 1e-6: the textbook law up to rounding;
  // syn-simulate uses more (ControllerOptions).
  double independence_cutoff = 1e-6;
  // μ in F_k's damped inverse λ/(λ² + μ²) on the kept rows' Φ' (eigenvalues O(1)): directions with
  // λ ≫ 1e-3 are within (μ/λ)² of exact, and a direction the cutoff lets through near a singularity
  // gets a force capped at 1/(2μ) in Φ' units. 0 gives the undamped textbook law.
  double damping = 1e-3;
};

class PrioritizedControl {
 public:
  explicit PrioritizedControl(const PrioritizedControlOptions& options = {}) : options_(options) {}

  // Γ (nu) for the state `workspace` holds (setQ and setU done; `mass` factored there): the task and
  // posture torques, without gravity and velocity terms. `posture_acceleration` (nu) is a_p.
  void calcTorques(Workspace& workspace, const TreeMassFactorization& mass, const std::vector<PriorityLevel>& levels,
                   const Eigen::VectorXd& posture_acceleration, Eigen::VectorXd& torques);

  // After calcTorques: A⁻¹ Γ_tasks (the acceleration the task torques alone give) and the rank each
  // level kept.
  const Eigen::VectorXd& taskAcceleration() const { return udot_tasks_; }
  int keptRank(size_t level) const { return solved_[level].rank; }
  // After calcTorques: whether `row` of `level` was among the rows kept.
  bool rowKept(size_t level, int row) const;

 private:
  struct SolvedLevel {
    Eigen::MatrixXd projected;   // J_k| [m_k, nu]
    Eigen::MatrixXd j_minv;      // J_k| A⁻¹ [m_k, nu] (A⁻¹ J_k|ᵀ transposed)
    Eigen::MatrixXd inertia;     // Λ_k [m_k, m_k]
    std::vector<Eigen::MatrixXd> couplings, weighted;  // J_k A⁻¹ J_j|ᵀ and that times Λ_j, per level j above
    Eigen::MatrixXd operational;     // Φ' = D J_k| A⁻¹ J_k|ᵀ D, then its pivoted Cholesky factor in place
    Eigen::MatrixXd unfactored;      // Φ' as it was, for the damped inverse
    std::vector<int> kept_rows;      // the rows the factorisation took, in pivot order (then the dropped)
    std::vector<char> row_kept;      // per row in the level's order: whether it was taken
    Eigen::VectorXd schur_diagonal;  // the factorisation's remaining pivots, in pivot order
    Eigen::MatrixXd factor_inverse;  // L⁻¹ of the kept rows' Cholesky factor
    Eigen::MatrixXd kept_inverse;    // Φ'_KK⁻¹ over the kept rows K, in pivot order
    Eigen::MatrixXd damped;          // Φ'_KK + μ² Φ'_KK⁻¹, whose inverse is the damped inverse
    Eigen::LLT<Eigen::MatrixXd> damped_factor;
    Eigen::VectorXd residual, force;                   // ẍ* − J̇u − J_k A⁻¹ Γ_{<k}, and F_k
    Eigen::VectorXd posture_residual, posture_force;   // the posture's projection scratch
    Eigen::VectorXd kept_residual, kept_force;         // D r and Φ'_KK's damped inverse of it, pivot order
    Eigen::VectorXd row_scale;       // D
    int rank = 0;
  };
  // Λ_k, F_k and the rank from the unit-diagonal Φ' (solved.operational), row_scale and residual.
  void invertKeptRows(SolvedLevel& solved, double independence_cutoff) const;
  PrioritizedControlOptions options_;
  std::vector<SolvedLevel> solved_;
  Eigen::VectorXd udot_tasks_, column_, product_;
};

}  // namespace syn
