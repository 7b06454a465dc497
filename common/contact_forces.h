// The base's residual from inverse dynamics, split into what the ground can push and what it cannot.
//
// Inverse dynamics without contact leaves generalized forces on the velocities no motor drives (a free
// base's six, or a virtual base chain's): the wrench the world must apply to the robot for the motion to
// happen. With the source's contacts known, the planted soles can supply part of it. Each sole point
// the robot map lists within `max_height` of the floor may push, if its foot is planted in the source or
// the point itself is slower than `max_speed` (a robot sole that is down while the source's ankle
// landmark counts as lifted: detection on an ankle releases a foot at heel-off, so a CMU walk has no
// double support in its labels), with a force in
// the friction cone (normal up, unilateral, |tangential| ≤ μ normal), linearised as an inscribed
// pyramid of eight edges; non-negative combinations of sole points keep each foot's centre of pressure
// inside its sole. The split is the non-negative least-squares fit of those forces to the residual
// wrench, both about the whole-body centre of mass in the ground frame (moments in N·m weighed against
// forces in N one to one, i.e. at 1 m); what the fit leaves is the unexplained residual, the number
// AddBiomechanics reports (2.5–5.7 N on its real-data fits). The fitted wrench is unique, its split
// over the points is not (two planted feet: a six-dimensional family of internal forces); of those
// splits the least-norm one (LeastNormConeCombination), unique and continuous in time, so a foot's
// share does not jump between frames.
//
// The residual wrench W is read from the unactuated generalized forces τ_b, whatever the base's
// parametrisation: with only the base's velocities moving, the whole robot moves rigidly with its first
// massive link, whose Jacobian J_b at the centre of mass maps them to a twist, so τ_b = J_bᵀ W.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "common/model.h"
#include "common/robot_map.h"
#include "common/least_norm_cone_combination.h"
#include "common/nonnegative_least_squares.h"

namespace syn {

struct ContactForceOptions {
  double friction = 0.8;     // μ; the default (rubber soles on a lab floor are 0.6–1.0)
  double max_height = 0.01;  // m: a sole point higher than this above z = 0 carries no force
  double max_speed = 0.5;    // m/s horizontal: an unplanted foot's sole point faster than this carries none
                             // (the GMD foot-skating speed)

  bool IsValid(std::string* error) const;
};

struct ContactForceFrame {
  Eigen::Matrix<double, 6, 1> residual;     // (moment about the centre of mass N·m, force N), ground frame
  Eigen::Matrix<double, 6, 1> unexplained;  // the part no admissible contact force explains
  std::vector<Eigen::Vector3d> foot_force;  // per robot-map foot, the sum of its sole points' forces (N)
  // Per sole point, every foot's points in the robot map's order one foot after another (N, ground).
  std::vector<Eigen::Vector3d> point_force;
};

class ContactForceSplit {
 public:
  // Throws DataError when the model has unactuated velocities but no single link they all move.
  ContactForceSplit(const Model& model, const std::vector<RobotFoot>& feet, const ContactForceOptions& options);

  // False for a model whose every velocity is actuated (a fixed base): nothing to split.
  bool hasBase() const { return base_link_ >= 0; }

  // One frame: the workspace at the frame's q (setQ), `u` its velocities, `tau` its inverse-dynamics
  // forces [nu], `planted` [feet] the source's contact flags. Allocates nothing.
  void split(Workspace& workspace, const Eigen::VectorXd& u, const Eigen::VectorXd& tau, const int64_t* planted,
             ContactForceFrame& out);

  // The same fit for a given wrench `wanted` (about the centre of mass, ground frame) instead of one read
  // from τ_b: out.residual = wanted, out.unexplained = what the sole forces leave of it. `row_weights`
  // (moment x, y, z, force x, y, z): the fit minimises Σ (w_i e_i)² over the unexplained part e, so where the
  // soles cannot explain the whole wrench, a component weighted more is left out less (syn-simulate's
  // --moment-weight; split() and the default weigh N·m against N one to one).
  void fit(Workspace& workspace, const Eigen::VectorXd& u, const Eigen::Matrix<double, 6, 1>& wanted, const int64_t* planted,
           ContactForceFrame& out, const Eigen::Matrix<double, 6, 1>& row_weights = Eigen::Matrix<double, 6, 1>::Ones());

  // X with W = X τ_b: the wrench about the centre of mass (ground frame) that generalized forces τ_b on the
  // base's unactuated velocities (in the model's order) amount to, at the workspace's q. X = J_b⁻ᵀ.
  Eigen::Matrix<double, 6, 6> wrenchFromBaseForces(Workspace& workspace);

 private:
  std::vector<RobotFoot> feet_;
  std::vector<int> foot_links_;
  ContactForceOptions options_;
  std::vector<int> unactuated_;  // the six velocity indices of the base
  int base_link_ = -1;
  std::vector<Eigen::Vector3d> edges_;  // friction pyramid edges, normal component 1
  Eigen::Matrix<double, 6, Eigen::Dynamic> jacobian_;
  Eigen::Matrix<double, 6, 1> foot_twist_;
  NonnegativeLeastSquares::Rows columns_;  // one per edge per sole point in contact
  NonnegativeLeastSquares::Rows weighted_columns_;  // the same, rows scaled by fit()'s row weights
  std::vector<int> column_foot_;
  std::vector<int> column_point_;  // the column's sole point, numbered as ContactForceFrame::point_force
  size_t point_count_ = 0;
  Eigen::VectorXd weights_;
  NonnegativeLeastSquares nonnegative_fit_;
  LeastNormConeCombination least_norm_;
  // The base's Jacobian at the centre of mass, its unactuated columns (τ_b = J_bᵀ W).
  Eigen::Matrix<double, 6, 6> baseJacobianAtCentre(Workspace& workspace);
};

}  // namespace syn
