// Natural cubic splines through sampled trajectories, evaluated at arbitrary
// times with their first derivative. Used wherever a stage needs a motion at
// a rate it was not sampled at (syn-evaluate's 1 kHz grid, syn-compose's
// time-warps).
//
// Each column of a [T, n] row-major table gets its own spline through the T
// knots; times must increase strictly. Evaluation walks a cursor forward, so
// monotone queries cost O(1) each and never allocate.
#pragma once

#include <cstdint>
#include <vector>

namespace syn {

class CubicSpline {
 public:
  CubicSpline() = default;
  // values: [T, n] row-major. T ≥ 2 (two knots give a straight line). Throws std::invalid_argument otherwise.
  CubicSpline(std::vector<double> times, std::vector<double> values, int64_t columns);

  int64_t columns() const { return columns_; }
  double startTime() const { return times_.front(); }
  double endTime() const { return times_.back(); }

  // value[n] and derivative[n] (either may be null) at time t, clamped to [startTime, endTime].
  void evaluate(double t, double* value, double* derivative) const;

 private:
  int64_t findInterval(double t) const;

  std::vector<double> times_, values_, second_derivatives_;
  int64_t columns_ = 0;
  mutable int64_t cursor_ = 0;
};

}  // namespace syn
