// The normal equations H x = g of a least-squares problem over a chain of
// equal-sized blocks x_0 … x_{N-1} in which every residual touches at most
// three consecutive blocks (a frame's tracking term, a second difference in
// time). H is then block-pentadiagonal and its Cholesky factor keeps that
// band, so the solve costs O(N n³) and needs no sparse symbolic analysis —
// the trajectory refinement solves one such system per window, and a general
// sparse solver's set-up was most of its time.
//
// Use: reset(), accumulate into diagonal()/lower()/rhs() (lower triangle of the
// diagonal blocks is enough), fix() the components that are held, solve().
#pragma once

#include <vector>

#include <Eigen/Core>

namespace syn {

class BlockBandedSystem {
 public:
  // N blocks of size n, all zero, nothing fixed. Storage is kept across calls of the same or smaller size.
  void reset(int blocks, int block_size);

  int blocks() const { return blocks_; }
  Eigen::MatrixXd& diagonal(int k) { return diagonal_[static_cast<size_t>(k)]; }
  // H_{k,k-distance}, distance 1 or 2 (the blocks above the diagonal are their transposes).
  Eigen::MatrixXd& lower(int k, int distance) {
    return (distance == 1 ? lower1_ : lower2_)[static_cast<size_t>(k)];
  }
  Eigen::VectorXd& rhs(int k) { return rhs_[static_cast<size_t>(k)]; }

  // Component i of block k is `value`, not an unknown.
  void fix(int k, int i, double value);

  // Solves in place; x[k] receives block k. Returns false when H (with the fixed components removed) is
  // not positive definite.
  bool solve(std::vector<Eigen::VectorXd>& x);

 private:
  void eliminateFixed();
  bool factorize();

  int blocks_ = 0, block_size_ = 0;
  std::vector<Eigen::MatrixXd> diagonal_, lower1_, lower2_;
  std::vector<Eigen::VectorXd> rhs_;
  std::vector<Eigen::VectorXd> fixed_value_;  // NaN: free
  bool any_fixed_ = false;
};

}  // namespace syn
