#include "stages/retarget/block_banded_system.h"

#include <cmath>
#include <limits>

#include <Eigen/Cholesky>

namespace syn {

void BlockBandedSystem::reset(int blocks, int block_size) {
  blocks_ = blocks;
  block_size_ = block_size;
  if (diagonal_.size() < static_cast<size_t>(blocks)) {
    diagonal_.resize(static_cast<size_t>(blocks));
    lower1_.resize(static_cast<size_t>(blocks));
    lower2_.resize(static_cast<size_t>(blocks));
    rhs_.resize(static_cast<size_t>(blocks));
    fixed_value_.resize(static_cast<size_t>(blocks));
  }
  for (size_t k = 0; k < static_cast<size_t>(blocks); ++k) {
    diagonal_[k].setZero(block_size, block_size);
    lower1_[k].setZero(block_size, block_size);
    lower2_[k].setZero(block_size, block_size);
    rhs_[k].setZero(block_size);
    fixed_value_[k].setConstant(block_size, std::numeric_limits<double>::quiet_NaN());
  }
  any_fixed_ = false;
}

void BlockBandedSystem::fix(int k, int i, double value) {
  fixed_value_[static_cast<size_t>(k)][i] = value;
  any_fixed_ = true;
}

// H_ff x_f = g_f − H_fc x_c, and the fixed rows become x_c = value. Zeroing a fixed component's row and
// column (diagonal 1) keeps the band, so the factorisation below does not need to know about them.
void BlockBandedSystem::eliminateFixed() {
  const int n = block_size_;
  for (int k = 0; k < blocks_; ++k) {
    const Eigen::VectorXd& value = fixed_value_[static_cast<size_t>(k)];
    for (int i = 0; i < n; ++i) {
      if (std::isnan(value[i])) continue;
      // Column (k, i) of H, block row by block row.
      rhs(k) -= value[i] * diagonal(k).col(i);
      if (k + 1 < blocks_) rhs(k + 1) -= value[i] * lower(k + 1, 1).col(i);
      if (k + 2 < blocks_) rhs(k + 2) -= value[i] * lower(k + 2, 2).col(i);
      if (k >= 1) rhs(k - 1) -= value[i] * lower(k, 1).row(i).transpose();
      if (k >= 2) rhs(k - 2) -= value[i] * lower(k, 2).row(i).transpose();
    }
  }
  for (int k = 0; k < blocks_; ++k) {
    const Eigen::VectorXd& value = fixed_value_[static_cast<size_t>(k)];
    for (int i = 0; i < n; ++i) {
      if (std::isnan(value[i])) continue;
      diagonal(k).row(i).setZero();
      diagonal(k).col(i).setZero();
      diagonal(k)(i, i) = 1.0;
      if (k + 1 < blocks_) lower(k + 1, 1).col(i).setZero();
      if (k + 2 < blocks_) lower(k + 2, 2).col(i).setZero();
      if (k >= 1) lower(k, 1).row(i).setZero();
      if (k >= 2) lower(k, 2).row(i).setZero();
      rhs(k)[i] = value[i];
    }
  }
}

// Block Cholesky H = L Lᵀ in place, L with the same band:
//   L_kk L_kkᵀ = H_kk − L_{k,k-1} L_{k,k-1}ᵀ − L_{k,k-2} L_{k,k-2}ᵀ
//   L_{k+1,k} = (H_{k+1,k} − L_{k+1,k-1} L_{k,k-1}ᵀ) L_kk⁻ᵀ,   L_{k+2,k} = H_{k+2,k} L_kk⁻ᵀ
bool BlockBandedSystem::factorize() {
  for (int k = 0; k < blocks_; ++k) {
    Eigen::MatrixXd& block = diagonal(k);
    if (k >= 1) block.selfadjointView<Eigen::Lower>().rankUpdate(lower(k, 1), -1.0);
    if (k >= 2) block.selfadjointView<Eigen::Lower>().rankUpdate(lower(k, 2), -1.0);
    Eigen::LLT<Eigen::Ref<Eigen::MatrixXd>, Eigen::Lower> cholesky(block);
    if (cholesky.info() != Eigen::Success) return false;
    const auto factor_transpose = block.triangularView<Eigen::Lower>().transpose();
    if (k + 1 < blocks_) {
      Eigen::MatrixXd& next = lower(k + 1, 1);
      if (k >= 1) next.noalias() -= lower(k + 1, 2) * lower(k, 1).transpose();
      factor_transpose.solveInPlace<Eigen::OnTheRight>(next);
    }
    if (k + 2 < blocks_) factor_transpose.solveInPlace<Eigen::OnTheRight>(lower(k + 2, 2));
  }
  return true;
}

bool BlockBandedSystem::solve(std::vector<Eigen::VectorXd>& x) {
  for (int k = 0; k < blocks_; ++k) {  // the callers fill the lower triangle; elimination reads columns
    Eigen::MatrixXd& block = diagonal(k);
    for (int j = 1; j < block_size_; ++j) {
      for (int i = 0; i < j; ++i) block(i, j) = block(j, i);
    }
  }
  if (any_fixed_) eliminateFixed();
  if (!factorize()) return false;
  for (int k = 0; k < blocks_; ++k) {  // L y = g
    if (k >= 1) rhs(k).noalias() -= lower(k, 1) * rhs(k - 1);
    if (k >= 2) rhs(k).noalias() -= lower(k, 2) * rhs(k - 2);
    diagonal(k).triangularView<Eigen::Lower>().solveInPlace(rhs(k));
  }
  for (int k = blocks_ - 1; k >= 0; --k) {  // Lᵀ x = y
    if (k + 1 < blocks_) rhs(k).noalias() -= lower(k + 1, 1).transpose() * rhs(k + 1);
    if (k + 2 < blocks_) rhs(k).noalias() -= lower(k + 2, 2).transpose() * rhs(k + 2);
    diagonal(k).triangularView<Eigen::Lower>().transpose().solveInPlace(rhs(k));
  }
  x.resize(static_cast<size_t>(blocks_));
  for (int k = 0; k < blocks_; ++k) x[static_cast<size_t>(k)] = rhs(k);
  return true;
}

}  // namespace syn
