// min ‖A x − b‖ subject to x ≥ 0, for A with six rows (a wrench) and a few dozen columns: Lawson and
// Hanson's active-set method (Solving Least Squares Problems, 1974, ch. 23). It ends in a finite number of
// steps at the exact optimum, where the KKT conditions hold: x ≥ 0, the gradient Aᵀ(A x − b) ≥ 0, and
// zero wherever x > 0. Its passive columns stay linearly independent, so at most six are ever solved
// for together and a solve allocates nothing once the solver is sized.
#pragma once

#include <Eigen/Core>

namespace syn {

class NonnegativeLeastSquares {
 public:
  using Rows = Eigen::Matrix<double, 6, Eigen::Dynamic>;

  explicit NonnegativeLeastSquares(int max_columns);

  // x (as many entries as A has columns, at most max_columns) minimises ‖A x − b‖ over x ≥ 0. Returns the
  // number of passive-set changes it took; stops (still feasible, possibly short of the optimum) after 3 n.
  int solve(const Eigen::Ref<const Rows>& a, const Eigen::Matrix<double, 6, 1>& b, Eigen::Ref<Eigen::VectorXd> x);

 private:
  Eigen::VectorXd gradient_, trial_;
  Eigen::VectorXi passive_;  // 1 = in the passive (free) set
  Eigen::VectorXi passive_columns_;
};

}  // namespace syn
