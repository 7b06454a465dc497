// The exact-constraint Gauss–Newton step (stages/retarget/constrained_step.h) against a dense KKT
// system solved independently (full-pivot LU), with equality rows, an active inequality and a bound.
#include <gtest/gtest.h>

#include <Eigen/LU>

#include <random>
#include "stages/retarget/constrained_step.h"

namespace syn {
namespace {

using RowMatrix = ConstrainedStep::RowMatrix;

// min ½‖r + JΔ‖² + ½λ‖Δ‖² s.t. E Δ + e = 0 (E: every row meant to be active, bounds as unit rows).
Eigen::VectorXd DenseKkt(const RowMatrix& j, const Eigen::VectorXd& r, double damping, const Eigen::MatrixXd& e,
                         const Eigen::VectorXd& rhs) {
  const int n = static_cast<int>(j.cols()), m = static_cast<int>(e.rows());
  Eigen::MatrixXd kkt = Eigen::MatrixXd::Zero(n + m, n + m);
  kkt.topLeftCorner(n, n) = j.transpose() * j + damping * Eigen::MatrixXd::Identity(n, n);
  kkt.topRightCorner(n, m) = e.transpose();
  kkt.bottomLeftCorner(m, n) = e;
  Eigen::VectorXd b(n + m);
  b.head(n) = -j.transpose() * r;
  b.tail(m) = -rhs;
  return kkt.fullPivLu().solve(b).head(n);
}

TEST(ConstrainedStep, EqualitiesMatchADenseKktSolve) {
  std::mt19937_64 random(7);
  std::normal_distribution<double> normal;
  const int n = 12, rows = 4;
  RowMatrix j(20, n);
  for (int i = 0; i < j.size(); ++i) j.data()[i] = normal(random);
  Eigen::VectorXd r(20);
  for (int i = 0; i < 20; ++i) r[i] = normal(random);
  ConstrainedStep step(n, 6);
  step.setRows(rows);
  for (int i = 0; i < rows; ++i) {
    for (int u = 0; u < n; ++u) step.a()(i, u) = normal(random);
    step.c()[i] = normal(random);
  }
  const Eigen::VectorXd lower = Eigen::VectorXd::Constant(n, -1e9), upper = Eigen::VectorXd::Constant(n, 1e9);
  Eigen::VectorXd delta(n);
  const double violation = step.solve(&j, &r, 1e-3, lower, upper, delta);
  EXPECT_LT(violation, 1e-9);
  const Eigen::VectorXd expected = DenseKkt(j, r, 1e-3, step.a().topRows(rows), step.c().head(rows));
  EXPECT_LT((delta - expected).norm(), 1e-8 * (1 + expected.norm()));
  // The constraints hold, and the unconstrained optimum would not have met them (so they did work).
  EXPECT_LT((step.a().topRows(rows) * delta + step.c().head(rows)).norm(), 1e-9);
  const Eigen::VectorXd free = DenseKkt(j, r, 1e-3, Eigen::MatrixXd(0, n), Eigen::VectorXd(0));
  EXPECT_GT((step.a().topRows(rows) * free + step.c().head(rows)).norm(), 0.1);
}

TEST(ConstrainedStep, InequalitiesAndBoundsJoinTheActiveSetOnlyWhenViolated) {
  // Two unknowns pulled to (1, 2). Row 0: Δ₀ + Δ₁ − 1 ≥ 0 is met at the optimum (stays inactive);
  // row 1: −Δ₁ + 1.5 ≥ 0 (Δ₁ ≤ 1.5) is violated by it (becomes active); Δ₀ ≤ 0.5 is a bound.
  RowMatrix j = RowMatrix::Identity(2, 2);
  Eigen::VectorXd r(2);
  r << -1, -2;
  ConstrainedStep step(2, 2);
  step.setRows(2);
  step.a() << 1, 1, 0, -1;
  step.c() << -1, 1.5;
  step.inequality()[0] = step.inequality()[1] = 1;
  Eigen::VectorXd lower(2), upper(2), delta(2);
  lower << -10, -10;
  upper << 0.5, 10;
  // (Tolerances 1e-9: the Schur complement carries a 1e-10 ridge, constrained_step.h says why.)
  const double violation = step.solve(&j, &r, 0.0, lower, upper, delta);
  EXPECT_LT(violation, 1e-9);
  EXPECT_NEAR(delta[0], 0.5, 1e-9);
  EXPECT_NEAR(delta[1], 1.5, 1e-9);
  // An inequality that is violated at the start but whose optimum lies inside is let go again:
  // Δ₀ ≥ 2 is impossible to keep with Δ₀ ≤ 0.5 … so take a satisfiable one: Δ₀ − 0.2 ≥ 0 starts violated
  // (c < 0) and the optimum 0.5 meets it without it binding.
  step.a() << 1, 0, 0, -1;
  step.c() << -0.2, 1.5;
  (void)step.solve(&j, &r, 0.0, lower, upper, delta);
  EXPECT_NEAR(delta[0], 0.5, 1e-9);
  EXPECT_NEAR(delta[1], 1.5, 1e-9);
}

TEST(ConstrainedStep, WithoutAJacobianItIsTheSmallestStepThatMeetsTheConstraints) {
  ConstrainedStep step(3, 1);
  step.setRows(1);
  step.a() << 1, 2, 2;  // ‖a‖ = 3
  step.c() << -3;
  Eigen::VectorXd lower = Eigen::VectorXd::Constant(3, -1e9), upper = Eigen::VectorXd::Constant(3, 1e9), delta(3);
  EXPECT_LT(step.solve(nullptr, nullptr, 0.0, lower, upper, delta), 1e-9);
  // Minimum norm: along aᵀ, a·Δ = 3 → Δ = a/3 (to the 1e-10 ridge of the Schur complement).
  EXPECT_NEAR(delta[0], 1.0 / 3.0, 1e-9);
  EXPECT_NEAR(delta[1], 2.0 / 3.0, 1e-9);
  EXPECT_NEAR(delta[2], 2.0 / 3.0, 1e-9);
}

}  // namespace
}  // namespace syn
