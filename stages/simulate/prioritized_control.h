// Strict task priorities by dynamically consistent null-space projection (Khatib 1987; Sentis & Khatib
// 2005), the controller of the paper's dynamic mapping.
//
// Levels k = 1..K, each a stack of task rows: J_k (m_k × nu) and the wanted task acceleration
// ẍ*_k (m_k). With A the mass matrix and N_{<k} the projector of every level above k:
//
//   J_k|  = J_k N_{<k}                      (the level restricted to what the levels above leave free)
//   Λ_k   = (J_k| A⁻¹ J_k|ᵀ)⁺               (task-space inertia; truncated pseudo-inverse, m_k × m_k)
//   J̄_k   = A⁻¹ J_k|ᵀ Λ_k                    (dynamically consistent generalized inverse)
//   F_k   = Λ̃_k (ẍ*_k − J̇_k u − J_k A⁻¹ Γ_{<k})   (Γ_{<k}: the task torques of the levels above; Λ̃_k
//           the damped inverse λ/(λ² + μ²) per eigen-direction, so a limb passing through a singularity
//           — a walking knee straightens every step — gets a bounded force, not 1/λ)
//   Γ_k   = J_k|ᵀ F_k,      N_{<k+1} = N_{<k} − J̄_k J_k|
//
// and after the last level the joint-space posture acceleration a_p enters as Γ_p = N_{<K+1}ᵀ A a_p,
// i.e. the part of a_p that leaves every task's acceleration alone. Γ = Σ Γ_k + Γ_p; the caller adds
// gravity and Coriolis compensation. The projectors use the undamped Λ_k, so a lower level's torque
// never changes a higher level's acceleration (J_j A⁻¹ J_k|ᵀ = 0 for j < k): level 1 tracks exactly
// as if level 2 did not exist. The damping only shortens F_k in nearly singular directions.
//
// Cost per call: Σ m_k products A⁻¹ x (substitutions with the caller's sparse factor of A, O(nu · depth)
// each) and one A x; A is never inverted. Only the m_k × m_k matrices are dense. No allocation after the first call
// with a given level layout.
#pragma once

#include <vector>

#include <Eigen/Core>
#include <Eigen/Eigenvalues>

#include "common/model.h"
#include "stages/simulate/tree_mass_factorization.h"

namespace syn {

struct PriorityLevel {
  Eigen::MatrixXd jacobian;       // J_k [m_k, nu]
  Eigen::VectorXd acceleration;   // ẍ*_k − J̇_k u [m_k]: the wanted task acceleration minus the velocity term
};

struct PrioritizedControlOptions {
  // Directions of the unit-diagonal Φ' = D J_k| A⁻¹ J_k|ᵀ D (see the .cpp) whose eigenvalue is below
  // this fraction of the largest are dropped from Λ_k's pseudo-inverse: a limb at a singularity then
  // gets no force there instead of an unbounded one, and the direction passes to the levels below
  // (so the strict priority holds for the directions a level keeps). 1e-6: the textbook law up to
  // rounding; syn-simulate uses 1e-2 (ControllerOptions).
  double singular_cutoff = 1e-6;
  // μ in F_k's damped inverse λ/(λ² + μ²) on Φ' (eigenvalues O(1)): directions with λ ≫ 1e-3 are
  // within (μ/λ)² of exact; a straightening knee's task inertia is capped at 1/(2μ) in Φ' units.
  // Without damping the 02_01 walk diverged within 80 ms. 0 gives the undamped textbook law.
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

 private:
  struct SolvedLevel {
    Eigen::MatrixXd projected;   // J_k| [m_k, nu]
    Eigen::MatrixXd j_minv;      // J_k| A⁻¹ [m_k, nu] (A⁻¹ J_k|ᵀ transposed)
    Eigen::MatrixXd inertia;     // Λ_k [m_k, m_k]
    std::vector<Eigen::MatrixXd> couplings, weighted;  // J_k A⁻¹ J_j|ᵀ and that times Λ_j, per level j above
    Eigen::MatrixXd operational, scaled;               // J_k| A⁻¹ J_k|ᵀ and its eigenvectors scaled
    Eigen::VectorXd residual, force;                   // ẍ* − J̇u − J_k A⁻¹ Γ_{<k}, and F_k
    Eigen::VectorXd posture_residual, posture_force;   // the posture's projection scratch
    Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen;
    Eigen::VectorXd inverse_eigenvalues, damped_inverse_eigenvalues;
    Eigen::VectorXd scaled_residual, term;  // F_k's products
    Eigen::VectorXd row_scale;       // D
    int rank = 0;
  };
  // Λ_k and F_k from the unit-diagonal Φ' (solved.operational), row_scale and residual.
  void invertByEigenvectors(SolvedLevel& solved) const;
  PrioritizedControlOptions options_;
  std::vector<SolvedLevel> solved_;
  Eigen::VectorXd udot_tasks_, column_, product_;
};

}  // namespace syn
