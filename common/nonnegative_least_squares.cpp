#include "common/nonnegative_least_squares.h"

#include <algorithm>
#include <limits>

#include <Eigen/QR>

namespace syn {
namespace {

// At most six passive columns: stack storage, so the per-frame solves never touch the heap.
using PassiveColumns = Eigen::Matrix<double, 6, Eigen::Dynamic, 0, 6, 6>;
using PassiveValues = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, 6, 1>;

}  // namespace

NonnegativeLeastSquares::NonnegativeLeastSquares(int max_columns)
    : gradient_(max_columns), trial_(max_columns), passive_(max_columns), passive_columns_(6) {}

int NonnegativeLeastSquares::solve(const Eigen::Ref<const Rows>& a, const Eigen::Matrix<double, 6, 1>& b,
                                   Eigen::Ref<Eigen::VectorXd> x) {
  const int n = static_cast<int>(a.cols());
  x.setZero();
  if (n == 0) return 0;
  auto passive = passive_.head(n);
  auto gradient = gradient_.head(n);  // −∂/∂x of ½‖A x − b‖²: positive where raising x lowers the cost
  passive.setZero();
  // Relative to the problem's own scale, so newtons and kilonewtons stop at the same digits.
  const double tolerance = 1e-12 * std::max(a.colwise().norm().maxCoeff() * b.norm(), std::numeric_limits<double>::min());
  const int limit = 3 * n;
  int changes = 0, passive_count = 0;
  int rejected = -1;  // a column whose own solve came out non-positive (rounding): skipped until x moves

  // The least-squares solution on the passive columns alone, scattered into trial_ (zero elsewhere).
  auto solve_passive = [&]() {
    trial_.head(n).setZero();
    if (passive_count == 0) return;
    PassiveColumns columns(6, passive_count);
    for (int k = 0, i = 0; i < n; ++i) {
      if (passive(i)) passive_columns_(k) = i, columns.col(k++) = a.col(i);
    }
    const PassiveValues values = columns.colPivHouseholderQr().solve(b);
    for (int k = 0; k < passive_count; ++k) trial_(passive_columns_(k)) = values(k);
  };

  gradient.noalias() = a.transpose() * (b - a * x);
  while (changes < limit && passive_count < 6) {
    int entering = -1;
    double largest = tolerance;
    for (int i = 0; i < n; ++i) {
      if (!passive(i) && i != rejected && gradient(i) > largest) largest = gradient(i), entering = i;
    }
    if (entering < 0) break;
    passive(entering) = 1, ++passive_count, ++changes;
    solve_passive();
    if (trial_(entering) <= 0) {
      passive(entering) = 0, --passive_count;
      rejected = entering;
      continue;
    }
    rejected = -1;
    // Move towards the passive set's solution until it is feasible, dropping the columns that reach zero.
    while ((trial_.head(n).array() <= 0 && passive.array() == 1).any() && changes < limit) {
      double step = 1.0;
      int blocking = -1;
      for (int i = 0; i < n; ++i) {
        if (passive(i) && trial_(i) <= 0 && x(i) / (x(i) - trial_(i)) <= step) {
          step = x(i) / (x(i) - trial_(i)), blocking = i;
        }
      }
      x += step * (trial_.head(n) - x);
      x(blocking) = 0;  // exactly, whatever the rounding of the step left
      for (int i = 0; i < n; ++i) {
        if (passive(i) && x(i) <= 0) passive(i) = 0, x(i) = 0, --passive_count, ++changes;
      }
      solve_passive();
    }
    for (int i = 0; i < n; ++i) x(i) = passive(i) ? trial_(i) : 0.0;
    gradient.noalias() = a.transpose() * (b - a * x);
  }
  return changes;
}

}  // namespace syn
