// Configuration-space maths, once for every stage (Pinocchio's integrate /
// difference / interpolate, for our layout): with a free base q = (quaternion
// w,x,y,z, position, joints...) [nq = nu + 1] and velocities v = (angular,
// linear, joints...) [nu], the base's angular part in the ground frame
// (left-multiplied, as Simbody's free mobilizer), its linear part the
// position's rate. Without a free base q and v are alike and the maths is
// plain vector arithmetic.
//
//   Integrate:    q1 = q0 ⊕ v        base: R1 = exp([v_ω]) R0, p1 = p0 + v_p
//   Difference:   v  = q1 ⊖ q0       so that q0 ⊕ (q1 ⊖ q0) = q1 (rotation angle ≤ π)
//   Interpolate:  q(s), s ∈ [0, 1]  linear; the base orientation by normalised lerp (nearer sign)
//
// Pointer forms are for hot loops (no allocation, no checks); the Eigen forms
// check sizes and say what they expected.
#pragma once

#include <Eigen/Core>

namespace syn {

// The shape of a configuration: whether it starts with a free base, and its sizes.
struct ConfigurationShape {
  bool free_base = false;
  int nq = 0;
  int nu = 0;

  static ConfigurationShape Of(bool free_base, int nq) { return {free_base, nq, free_base ? nq - 1 : nq}; }
};

void Integrate(const ConfigurationShape& shape, const double* q0, const double* v, double* q1);
void Difference(const ConfigurationShape& shape, const double* q0, const double* q1, double* v);
void Interpolate(const ConfigurationShape& shape, const double* q0, const double* q1, double s, double* q);
// Interpolate without the final normalisation: the base quaternion is left on the chord, off the unit sphere.
// For a caller whose consumer normalises anyway (Workspace::setQ does): normalising twice rounds differently
// from normalising once, and the segmentation's ΔP is then no longer the same to the last bit.
void InterpolateUnnormalized(const ConfigurationShape& shape, const double* q0, const double* q1, double s,
                             double* q);

// Checked forms: throw std::invalid_argument naming the argument, the expected and the actual size.
void Integrate(const ConfigurationShape& shape, const Eigen::VectorXd& q0, const Eigen::VectorXd& v, Eigen::VectorXd& q1);
void Difference(const ConfigurationShape& shape, const Eigen::VectorXd& q0, const Eigen::VectorXd& q1, Eigen::VectorXd& v);
void Interpolate(const ConfigurationShape& shape, const Eigen::VectorXd& q0, const Eigen::VectorXd& q1, double s,
                 Eigen::VectorXd& q);

// Rotation-vector maths for the base's turn (φ = axis × angle, in the ground frame, as Integrate's):
// CrossMatrix(v) w = v × w.
Eigen::Matrix3d CrossMatrix(const Eigen::Vector3d& v);
// SO(3)'s left Jacobian at φ: turning by φ + δ is turning by φ, then by RotationLeftJacobian(φ) δ on top
// (ground frame).
Eigen::Matrix3d RotationLeftJacobian(const Eigen::Vector3d& phi);
// Its inverse: d log(E)/dω for E = R R*ᵀ, φ = log(E), and a ground-frame angular velocity ω of R. It is I
// only near φ = 0; an unreachable target leaves errors of tens of degrees, where I is wrong.
Eigen::Matrix3d RotationLeftJacobianInverse(const Eigen::Vector3d& phi);

// Throws std::invalid_argument("`what`: expected N values, got M") unless size == expected.
void CheckSize(const char* what, Eigen::Index expected, Eigen::Index size);

}  // namespace syn
