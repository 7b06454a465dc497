#include <gtest/gtest.h>

#include <random>

#include <Eigen/Dense>

#include "stages/retarget/block_banded_system.h"

namespace syn {
namespace {

// A random symmetric positive-definite block-pentadiagonal matrix, solved with some components held,
// against a dense LDLT of the same equations with the held components substituted.
TEST(BlockBandedSystem, MatchesDenseSolveWithHeldComponents) {
  const int blocks = 9, n = 4, size = blocks * n;
  std::mt19937 random(7);
  std::normal_distribution<double> normal;
  // H = Aᵀ A + I with A banded: each row of A touches three consecutive blocks.
  Eigen::MatrixXd A = Eigen::MatrixXd::Zero(size, size);
  for (int k = 0; k < blocks; ++k) {
    for (int row = k * n; row < (k + 1) * n; ++row) {
      for (int col = std::max(0, (k - 1) * n); col < std::min(size, (k + 2) * n); ++col) A(row, col) = normal(random);
    }
  }
  const Eigen::MatrixXd H = A.transpose() * A + Eigen::MatrixXd::Identity(size, size);
  Eigen::VectorXd g(size);
  for (int i = 0; i < size; ++i) g[i] = normal(random);
  const std::vector<std::pair<int, double>> held = {{0, 0.5}, {5, -1.25}, {17, 2.0}, {18, 0.0}, {35, 3.0}};

  BlockBandedSystem system;
  system.reset(blocks, n);
  for (int k = 0; k < blocks; ++k) {
    system.diagonal(k) = H.block(k * n, k * n, n, n).triangularView<Eigen::Lower>();  // only the lower triangle
    if (k >= 1) system.lower(k, 1) = H.block(k * n, (k - 1) * n, n, n);
    if (k >= 2) system.lower(k, 2) = H.block(k * n, (k - 2) * n, n, n);
    system.rhs(k) = g.segment(k * n, n);
  }
  for (const auto& [index, value] : held) system.fix(index / n, index % n, value);
  std::vector<Eigen::VectorXd> x;
  ASSERT_TRUE(system.solve(x));

  std::vector<int> free;
  Eigen::VectorXd fixed_values = Eigen::VectorXd::Zero(size);
  std::vector<bool> is_held(size, false);
  for (const auto& [index, value] : held) {
    is_held[static_cast<size_t>(index)] = true;
    fixed_values[index] = value;
  }
  for (int i = 0; i < size; ++i) {
    if (!is_held[static_cast<size_t>(i)]) free.push_back(i);
  }
  const Eigen::VectorXd reduced_rhs = g - H * fixed_values;
  Eigen::MatrixXd H_ff(free.size(), free.size());
  Eigen::VectorXd g_f(free.size());
  for (size_t a = 0; a < free.size(); ++a) {
    g_f[static_cast<Eigen::Index>(a)] = reduced_rhs[free[a]];
    for (size_t b = 0; b < free.size(); ++b) H_ff(static_cast<Eigen::Index>(a), static_cast<Eigen::Index>(b)) = H(free[a], free[b]);
  }
  const Eigen::VectorXd x_f = H_ff.ldlt().solve(g_f);
  Eigen::VectorXd expected = fixed_values;
  for (size_t a = 0; a < free.size(); ++a) expected[free[a]] = x_f[static_cast<Eigen::Index>(a)];

  ASSERT_EQ(x.size(), static_cast<size_t>(blocks));
  for (int i = 0; i < size; ++i) EXPECT_NEAR(x[static_cast<size_t>(i / n)][i % n], expected[i], 1e-10) << "component " << i;
}

TEST(BlockBandedSystem, ReportsASingularSystem) {
  BlockBandedSystem system;
  system.reset(3, 2);
  for (int k = 0; k < 3; ++k) system.diagonal(k).setIdentity();
  system.diagonal(1)(1, 1) = 0.0;  // one unknown that nothing determines
  std::vector<Eigen::VectorXd> x;
  EXPECT_FALSE(system.solve(x));
}

}  // namespace
}  // namespace syn
