// Postural synergies of one motion segment (paper, Eq. "vel_recon"; DESIGN.md,
// Method: Synergies), as every stage that reads them sees them:
//
//   X − mean = U Σ Vᵀ   (X: [Ts, nv] velocity samples, one row per frame)
//   synergy i: direction V_i (row i of `components`), coefficient a_i (σ_i by
//   default), time profile U_i(t) (column i of `scores`, unit norm)
//   û(t) = mean + Σ_{i≤k} a_i U_i(t) V_i
//
// syn-synergies computes them (stages/synergies/segment_pca.h); evaluate,
// compose and project reconstruct velocities from them.
#pragma once

#include <Eigen/Core>

namespace syn {

struct SegmentSynergies {
  Eigen::VectorXd mean;                 // [nv]
  Eigen::MatrixXd components;           // [k, nv], orthonormal rows
  Eigen::VectorXd singular_values;      // [k]
  Eigen::VectorXd explained_variance_ratio;  // [k], σ_i² / Σ_all σ²
  Eigen::MatrixXd scores;               // [Ts, k], unit-norm columns U_i
  int components_for_90_percent = 0;    // smallest k reaching ≥ 90 % of the variance
};

// û(t) for coefficients a (size ≤ k; defaults to the singular values).
[[nodiscard]] Eigen::MatrixXd ReconstructVelocities(const SegmentSynergies& synergies, const Eigen::VectorXd& coefficients);

}  // namespace syn
