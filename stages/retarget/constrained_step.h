// One Gauss–Newton step with exact constraints, for the per-frame IK's contact
// constraints (frame_ik.h): over a velocity-space step Δ,
//
//   minimise   ½‖r + J Δ‖² + ½ λ‖Δ‖²
//   subject to a_i Δ + c_i = 0    (equality rows: a planted foot's pose)
//              a_i Δ + c_i ≥ 0    (inequality rows: a sole point's height)
//              lo ≤ Δ ≤ hi        (joint limits, the per-frame velocity bound)
//
// solved by the range-space method: H = JᵀJ + λI by Cholesky, then the
// multipliers from the small Schur complement S = A H⁻¹ Aᵀ. Inequality rows
// and box bounds are handled by an active set (a violated row or bound joins
// it; an inequality whose multiplier pulls the point down leaves it). Every
// size is fixed at construction (inactive rows are zero rows with a unit
// diagonal in S), so a solve allocates nothing. Without J (a projection), the
// step is the smallest ‖Δ‖ that meets the constraints.
#pragma once

#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

namespace syn {

class ConstrainedStep {
 public:
  using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

  ConstrainedStep(int unknowns, int max_rows);

  // The constraint rows of this step: A (max_rows × n, rows ≥ rows() unused), c, and per row whether it is an
  // inequality. Fill, then call solve.
  Eigen::MatrixXd& a() { return a_; }
  Eigen::VectorXd& c() { return c_; }
  std::vector<uint8_t>& inequality() { return inequality_; }
  void setRows(int rows) { rows_ = rows; }
  int rows() const { return rows_; }

  // jacobian/residual null: a minimum-norm projection. Returns the largest remaining equality violation
  // (or inequality violation) predicted by the linearisation: 0 when every constraint can be met.
  double solve(const RowMatrix* jacobian, const Eigen::VectorXd* residual, double damping, const Eigen::VectorXd& lower,
               const Eigen::VectorXd& upper, Eigen::VectorXd& step);

 private:
  void solveWithActiveSet(Eigen::VectorXd& step);

  int n_, max_rows_, rows_ = 0;
  Eigen::MatrixXd a_, a_active_, h_, h_inv_at_, s_;
  Eigen::VectorXd c_, c_active_, g_, step0_, mu_, free_rhs_;
  std::vector<uint8_t> inequality_, active_, held_;
  Eigen::VectorXd held_value_;
  Eigen::LLT<Eigen::MatrixXd> h_factor_, s_factor_;
  // The problem's fixed parts, kept between the active-set rounds.
  Eigen::MatrixXd jtj_;
  Eigen::VectorXd jtr_;
};

}  // namespace syn
