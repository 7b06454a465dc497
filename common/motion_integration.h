// From generalized velocities back to configurations: q̂(t) = q0 ⊕ ∫ û dt,
// quaternion-aware for a free base. Shared by syn-evaluate (Monte-Carlo
// reconstructions), syn-compose and syn-project.
//
// Layout (common/model.h): with a free base q = (quaternion w,x,y,z, position,
// joints...) and u = (angular velocity, linear velocity, joints...), the base
// velocities in the ground frame. Synergies store the base velocities in the
// pelvis heading frame instead (yaw removed, stages/synergies/synergies.h);
// BaseVelocityFrame::kHeading turns them back with the yaw of the pose being
// integrated, so a synergy replayed from a different facing direction turns
// with it.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

namespace syn {

enum class BaseVelocityFrame { kGround, kHeading };

// Yaw (rad) of the base orientation quaternion (w, x, y, z): the heading of its X axis in the ground plane.
[[nodiscard]] double BaseYaw(const double* quaternion_wxyz);

// A quaternion and its negative are one rotation: flips base quaternions (the first four entries of each
// [T, nq] row-major row) so that neighbours agree in sign, as interpolating them needs.
void MakeBaseQuaternionsContinuous(std::vector<double>& q, int64_t nq);

// Rotates the six base velocities of u (angular, linear) about Z by `yaw` in place.
void RotateBaseVelocities(double yaw, double* u);

// Integrates velocities sampled at `times` [T] (rows of `velocities`, [T, nu]) from `q0` [nq] by the
// trapezoidal rule; a free base's orientation by the exponential map of the mean angular velocity
// (left-multiplied: the velocity is in the ground frame). Heading-frame base velocities are turned
// with a predictor-corrector on the yaw. Fills q [T, nq] and the ground-frame velocities [T, nu].
void IntegrateVelocities(bool free_base, const Eigen::VectorXd& q0, const Eigen::VectorXd& times,
                         const Eigen::MatrixXd& velocities, BaseVelocityFrame frame, Eigen::MatrixXd& q,
                         Eigen::MatrixXd& ground_velocities);

// One step of the same rule: q1 = q0 ⊕ dt (v0 + v1) / 2, ground-frame velocities.
void StepConfiguration(bool free_base, const double* q0, const double* v0, const double* v1, double dt, int nq,
                       double* q1);

}  // namespace syn
