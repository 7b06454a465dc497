// The dynamically consistent null space of the upper-torso orientation task
// (paper, "Projection of text-to-motion output"; Khatib's operational-space
// formulation):
//
//   J_t: the 3 angular rows of the torso link's frame Jacobian (ground frame)
//   Λ_t = (J_t A⁻¹ J_tᵀ)⁻¹,   J̄_t = A⁻¹ J_tᵀ Λ_t,   N_t = I − J̄_t J_t
//
// Per configuration, A⁻¹ J_tᵀ takes three of Simbody's O(n) A⁻¹ products (A
// is never formed or inverted); Λ_t is a 3 × 3 solve. Applying N_t or its
// complement J̄_t J_t to a velocity is then O(n).
#pragma once

#include <Eigen/Core>

#include "common/model.h"

namespace syn {

class TorsoNullSpace {
 public:
  TorsoNullSpace(const Model& model, int torso_link);

  // Evaluates J_t, A⁻¹ J_tᵀ and Λ_t at q. Allocation-free after construction.
  void setConfiguration(const Eigen::VectorXd& q);

  // out = N_t u.
  void applyNullSpace(const Eigen::VectorXd& u, Eigen::VectorXd& out) const;
  // out = J̄_t J_t u = (I − N_t) u: the part of u that moves the torso's orientation.
  void applyTaskSpace(const Eigen::VectorXd& u, Eigen::VectorXd& out) const;

  const Eigen::Matrix<double, 3, Eigen::Dynamic>& jacobian() const { return jacobian_; }
  const Eigen::Matrix<double, Eigen::Dynamic, 3>& inverseMassTimesJacobianTranspose() const { return minv_jt_; }

 private:
  Workspace workspace_;
  int link_;
  Eigen::Matrix<double, 6, Eigen::Dynamic> frame_jacobian_;
  Eigen::Matrix<double, 3, Eigen::Dynamic> jacobian_;
  Eigen::Matrix<double, Eigen::Dynamic, 3> minv_jt_;
  Eigen::Matrix3d lambda_;
  Eigen::VectorXd column_, product_;
};

}  // namespace syn
