// The free base's residual wrench split into contact forces and what no
// admissible contact force explains (issue 17).
//
// Inverse dynamics with no contact leaves, on a free base's six unactuated
// velocities, the wrench the world must apply to the pelvis for the motion to
// happen: a moment about the pelvis origin and a force, both in the ground
// frame. Feet on the floor can supply part of it. Each sole point within
// `touch_height` of z = 0 may push with a force inside the friction pyramid
// (coefficient μ: four edges n ± μ t₁, n ± μ t₂), so the admissible wrenches
// are the non-negative combinations of the edges' wrenches — unilateral normal
// force, friction bounded by μ, and the centre of pressure inside each sole's
// convex hull. Non-negative least squares (Lawson–Hanson) finds the
// combination closest to the residual; what is left is the unexplained part:
// the motion asks for a wrench no contact could provide (a foot sliding, a
// body leaning beyond its support, a pelvis rotating by itself).
//
// Defaults: μ = 0.8 (issue 17; rubber soles on a hard floor, e.g. 0.7–1.0 in
// legged-robot friction measurements); a point counts as touching within 5 mm
// of the floor (the contact constraints put planted soles at exactly 0).
#pragma once

#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

namespace syn {

struct ContactForceOptions {
  double friction = 0.8;
  double touch_height = 0.005;  // m
};

// Non-negative least squares min ‖A x − b‖, x ≥ 0, by Lawson and Hanson's active set (1974). All sizes
// fixed at construction (columns ≤ max_columns), so a solve allocates nothing.
class NonNegativeLeastSquares {
 public:
  NonNegativeLeastSquares(int rows, int max_columns);
  // A: rows × columns (the first `columns` columns of `a()`). Returns x in `x().head(columns)`.
  Eigen::MatrixXd& a() { return a_; }
  const Eigen::VectorXd& x() const { return x_; }
  void solve(int columns, const Eigen::VectorXd& b);

 private:
  void solvePassive(int columns, const Eigen::VectorXd& b, Eigen::VectorXd& z);

  int rows_, max_columns_;
  Eigen::MatrixXd a_, ata_, reduced_;
  Eigen::VectorXd x_, z_, w_, atb_, reduced_rhs_, reduced_solution_;
  Eigen::LDLT<Eigen::MatrixXd> factor_;
  std::vector<uint8_t> passive_;
  std::vector<int> index_;
};

// One frame's split. sole_points: every foot's sole points in the ground frame (feet concatenated, with
// foot_of_point giving each point's foot). residual: the base's [moment about base_origin, force].
// Outputs: per foot the total contact force (N, ground frame) and the unexplained [moment, force].
class ContactForceSplit {
 public:
  ContactForceSplit(int max_points, const ContactForceOptions& options);
  void split(const std::vector<Eigen::Vector3d>& sole_points, const std::vector<int>& foot_of_point, int feet,
             const Eigen::Vector3d& base_origin, const Eigen::Matrix<double, 6, 1>& residual,
             std::vector<Eigen::Vector3d>& foot_force, Eigen::Matrix<double, 6, 1>& unexplained);

 private:
  ContactForceOptions options_;
  NonNegativeLeastSquares nnls_;
  Eigen::VectorXd target_;
  std::vector<int> column_point_;
  std::vector<Eigen::Vector3d> column_direction_;
};

}  // namespace syn
