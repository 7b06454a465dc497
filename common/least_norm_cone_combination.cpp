#include "common/least_norm_cone_combination.h"

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

namespace syn {
namespace {

// Eigenvalues of A_F A_Fᵀ below this fraction of the largest are treated as zero (directions the free
// columns do not span, where w has no component).
constexpr double kRankCutoff = 1e-12;
// A Cholesky factor whose every pivot exceeds this fraction of the Gram's trace (≥ its largest eigenvalue)
// is far from rank-deficient: its solve is the pseudo-inverse's to rounding, at a tenth of an
// eigen-decomposition's cost (which took a third of ground mode's time). Near that, the eigen-decomposition
// decides the rank.
constexpr double kWellConditionedPivot = 1e-8;
// The step to the free columns' optimum counts as zero below this fraction of ‖x‖ (+1). The optimum is
// solved to about 10⁻¹¹ of ‖x‖; at 10⁻¹² a step of rounding's size was taken as a real one, and held a
// column it had just freed.
constexpr double kStepTolerance = 1e-9;

}  // namespace

LeastNormConeCombination::LeastNormConeCombination(int max_columns)
    : target_(max_columns), held_(max_columns), tried_(max_columns) {}

int LeastNormConeCombination::solve(const Eigen::Ref<const NonnegativeLeastSquares::Rows>& a, Eigen::Ref<Eigen::VectorXd> x) {
  const Eigen::Index n = a.cols();
  if (n == 0) return 0;
  const Eigen::Matrix<double, 6, 1> w = a * x;
  const double scale = a.colwise().norm().maxCoeff();
  const double tolerance = kStepTolerance * (x.norm() + 1.0);
  auto target = target_.head(n);
  auto held = held_.head(n);
  auto tried = tried_.head(n);
  tried.setConstant(false);
  // The first working set: the columns both x and the unconstrained least-norm solution leave at zero
  // or below. (Any subset of x's zero columns is valid; this one is usually right at once, where holding
  // all of them would free them one per iteration.)
  held.setConstant(false);
  Eigen::SelfAdjointEigenSolver<Eigen::Matrix<double, 6, 6>> eigen;
  Eigen::LLT<Eigen::Matrix<double, 6, 6>> cholesky;
  const int max_iterations = 4 * static_cast<int>(n) + 10;
  int iteration = 0;
  for (; iteration < max_iterations; ++iteration) {
    Eigen::Matrix<double, 6, 6> gram = Eigen::Matrix<double, 6, 6>::Zero();
    for (Eigen::Index c = 0; c < n; ++c) {
      if (!held[c]) gram.selfadjointView<Eigen::Lower>().rankUpdate(a.col(c));
    }
    gram = gram.selfadjointView<Eigen::Lower>();
    Eigen::Matrix<double, 6, 1> multiplier;
    cholesky.compute(gram);
    const bool well_conditioned =
        cholesky.info() == Eigen::Success &&
        cholesky.matrixLLT().diagonal().cwiseAbs2().minCoeff() > kWellConditionedPivot * std::max(gram.trace(), scale * scale);
    if (well_conditioned) {
      multiplier = cholesky.solve(w);
    } else {
      eigen.compute(gram);
      const double cutoff = kRankCutoff * std::max(eigen.eigenvalues().maxCoeff(), scale * scale);
      Eigen::Matrix<double, 6, 1> projected = eigen.eigenvectors().transpose() * w;
      for (int k = 0; k < 6; ++k) projected[k] = eigen.eigenvalues()[k] > cutoff ? projected[k] / eigen.eigenvalues()[k] : 0.0;
      multiplier = eigen.eigenvectors() * projected;
    }
    target.noalias() = a.transpose() * multiplier;
    if (iteration == 0) {
      for (Eigen::Index c = 0; c < n; ++c) held[c] = !(x[c] > 0) && !(target[c] > 0);
      if (held.any()) continue;  // the free columns' own least-norm solution next
    }
    // Towards y on the free columns, as far as they stay non-negative.
    double length = 1.0;
    Eigen::Index blocking = -1;
    double step_norm = 0;
    for (Eigen::Index c = 0; c < n; ++c) {
      if (held[c]) continue;
      const double step = target[c] - x[c];
      step_norm = std::max(step_norm, std::abs(step));
      if (step < 0 && x[c] + length * step < 0) length = x[c] / -step, blocking = c;
    }
    if (step_norm > tolerance) {
      for (Eigen::Index c = 0; c < n; ++c) {
        if (!held[c]) x[c] += length * (target[c] - x[c]);
      }
      if (blocking >= 0) x[blocking] = 0.0, held[blocking] = true;
      if (length * step_norm > tolerance) tried.setConstant(false);  // x moved: every column may be freed again
      continue;
    }
    // At the free columns' optimum: free the held column whose multiplier is most negative, or stop. A
    // degenerate vertex (more columns at zero than the wrench needs) can hold again, with no move, the
    // column just freed, and free it again: on CMU walks onto G1 a quarter of the calls cycled so until the
    // iteration cap. So a column freed once is not freed again until x moves.
    Eigen::Index freed = -1;
    double most = tolerance * scale;
    for (Eigen::Index c = 0; c < n; ++c) {
      if (held[c] && !tried[c] && target[c] > most) most = target[c], freed = c;
    }
    if (freed < 0) break;
    held[freed] = false;
    tried[freed] = true;
  }
  for (Eigen::Index c = 0; c < n; ++c) x[c] = held[c] ? 0.0 : std::max(0.0, x[c]);
  return iteration;
}

}  // namespace syn
