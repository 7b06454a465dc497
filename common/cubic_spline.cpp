#include "common/cubic_spline.h"

#include <algorithm>
#include <stdexcept>
#include <string>

namespace syn {

CubicSpline::CubicSpline(std::vector<double> times, std::vector<double> values, int64_t columns)
    : times_(std::move(times)), values_(std::move(values)), columns_(columns) {
  const int64_t knots = static_cast<int64_t>(times_.size());
  if (knots < 2 || columns_ < 1 || static_cast<int64_t>(values_.size()) != knots * columns_) {
    throw std::invalid_argument("cubic spline needs at least 2 knots and [knots, columns] values");
  }
  for (int64_t k = 1; k < knots; ++k) {
    if (!(times_[static_cast<size_t>(k)] > times_[static_cast<size_t>(k - 1)])) {
      throw std::invalid_argument("cubic spline knot times must increase strictly (knot " + std::to_string(k) + ")");
    }
  }
  // Natural end conditions (zero second derivative); the tridiagonal system is solved by the Thomas
  // algorithm for all columns at once, one knot row at a time.
  second_derivatives_.assign(values_.size(), 0.0);
  std::vector<double> diagonal(static_cast<size_t>(knots), 1.0), upper(static_cast<size_t>(knots), 0.0);
  auto y = [&](int64_t k, int64_t c) { return values_[static_cast<size_t>(k * columns_ + c)]; };
  auto m = [&](int64_t k, int64_t c) -> double& { return second_derivatives_[static_cast<size_t>(k * columns_ + c)]; };
  for (int64_t k = 1; k + 1 < knots; ++k) {
    const double h0 = times_[static_cast<size_t>(k)] - times_[static_cast<size_t>(k - 1)];
    const double h1 = times_[static_cast<size_t>(k + 1)] - times_[static_cast<size_t>(k)];
    const double lower = h0 / 6.0;
    const double pivot = (h0 + h1) / 3.0 - lower * upper[static_cast<size_t>(k - 1)] / diagonal[static_cast<size_t>(k - 1)];
    diagonal[static_cast<size_t>(k)] = pivot;
    upper[static_cast<size_t>(k)] = h1 / 6.0;
    for (int64_t c = 0; c < columns_; ++c) {
      const double rhs = (y(k + 1, c) - y(k, c)) / h1 - (y(k, c) - y(k - 1, c)) / h0;
      m(k, c) = rhs - lower * m(k - 1, c) / diagonal[static_cast<size_t>(k - 1)];
    }
  }
  for (int64_t k = knots - 2; k >= 1; --k) {
    for (int64_t c = 0; c < columns_; ++c) {
      m(k, c) = (m(k, c) - upper[static_cast<size_t>(k)] * m(k + 1, c)) / diagonal[static_cast<size_t>(k)];
    }
  }
}

int64_t CubicSpline::findInterval(double t) const {
  const int64_t last = static_cast<int64_t>(times_.size()) - 2;
  if (cursor_ > last || t < times_[static_cast<size_t>(cursor_)]) {
    const auto it = std::upper_bound(times_.begin(), times_.end(), t);
    cursor_ = std::clamp<int64_t>(static_cast<int64_t>(it - times_.begin()) - 1, 0, last);
  }
  while (cursor_ < last && t >= times_[static_cast<size_t>(cursor_ + 1)]) ++cursor_;
  return cursor_;
}

void CubicSpline::evaluate(double t, double* value, double* derivative) const {
  t = std::clamp(t, times_.front(), times_.back());
  const int64_t k = findInterval(t);
  const double t0 = times_[static_cast<size_t>(k)], t1 = times_[static_cast<size_t>(k + 1)];
  const double h = t1 - t0, a = (t1 - t) / h, b = (t - t0) / h;
  const double* y0 = &values_[static_cast<size_t>(k * columns_)];
  const double* y1 = y0 + columns_;
  const double* m0 = &second_derivatives_[static_cast<size_t>(k * columns_)];
  const double* m1 = m0 + columns_;
  const double curve0 = (a * a * a - a) * h * h / 6.0, curve1 = (b * b * b - b) * h * h / 6.0;
  const double slope0 = -(3.0 * a * a - 1.0) * h / 6.0, slope1 = (3.0 * b * b - 1.0) * h / 6.0;
  for (int64_t c = 0; c < columns_; ++c) {
    if (value) value[c] = a * y0[c] + b * y1[c] + curve0 * m0[c] + curve1 * m1[c];
    if (derivative) derivative[c] = (y1[c] - y0[c]) / h + slope0 * m0[c] + slope1 * m1[c];
  }
}

}  // namespace syn
