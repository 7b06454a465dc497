// Postural synergies of one motion segment: PCA of its generalized-velocity
// samples (paper, Eq. "vel_recon"; DESIGN.md, Method: Synergies).
//
//   X − mean = U Σ Vᵀ   (X: [Ts, nv] velocity samples, one row per frame)
//   synergy i: direction V_i (row i of `components`), coefficient a_i (σ_i by
//   default), time profile U_i(t) (column i of `scores`, unit norm)
//   û(t) = mean + Σ_{i≤k} a_i U_i(t) V_i
//
// Signs are fixed so that each direction's largest entry is positive, which
// makes the output deterministic (an SVD may return either sign).
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

// k is capped at min(Ts, nv). Throws std::invalid_argument for an empty X.
[[nodiscard]] SegmentSynergies ComputeSegmentSynergies(const Eigen::MatrixXd& velocities, int components);

// û(t) for coefficients a (size ≤ k; defaults to the singular values).
[[nodiscard]] Eigen::MatrixXd ReconstructVelocities(const SegmentSynergies& synergies, const Eigen::VectorXd& coefficients);

}  // namespace syn
