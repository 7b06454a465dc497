// Among the non-negative combinations x of A's columns that give the same wrench A x, the one of least
// norm ‖x‖.
//
// Why: a wrench that contact forces explain has many splits over the sole points when more than six
// pyramid edges touch (two planted feet: a six-dimensional family of internal forces). A least-squares
// fit with x ≥ 0 lands on a vertex of that family, and which vertex jumps from frame to frame with the
// wrench, so the share each foot carries, and any joint torque computed from it, jumps with it. The
// least-norm split is unique and continuous in the wrench: it spreads the load over every touching
// point, the pseudo-inverse distribution of force-control practice, kept inside the cones.
//
// Method: a primal active-set method (Nocedal and Wright, Numerical Optimization, §16.5) for
// min ½‖x‖² subject to A x = w, x ≥ 0, started from the given feasible x (the non-negative fit's). The
// columns held at zero form the working set; on the free ones, the least-norm solution of A_F y = w is
// y = A_Fᵀ μ with (A_F A_Fᵀ) μ = w (a 6×6 system, pseudo-inverted where the free columns span less
// than six dimensions). The step towards y stops at the first column it would make negative, which
// joins the working set; at y, a held column with A_iᵀ μ > 0 (its multiplier negative) is freed. Every
// step keeps A x = w, so the wrench is reproduced to rounding, also where it lies on the cone's boundary
// (a dual method's multipliers run off to infinity there). At a degenerate vertex (more columns at zero
// than w needs) a freed column can be held again at once with no move; it is not freed again until x
// moves, which ends the method where it had cycled to its iteration cap on a quarter of ground mode's calls.
#pragma once

#include <Eigen/Core>

#include "common/nonnegative_least_squares.h"

namespace syn {

class LeastNormConeCombination {
 public:
  explicit LeastNormConeCombination(int max_columns);

  // x: on entry non-negative weights of A's columns; on return the non-negative weights of least norm
  // with the same A x. Returns the active-set iterations taken. Allocates nothing once sized.
  int solve(const Eigen::Ref<const NonnegativeLeastSquares::Rows>& a, Eigen::Ref<Eigen::VectorXd> x);

 private:
  Eigen::VectorXd target_;
  Eigen::Matrix<bool, Eigen::Dynamic, 1> held_;   // in the working set: held at zero
  Eigen::Matrix<bool, Eigen::Dynamic, 1> tried_;  // freed since x last moved
};

}  // namespace syn
