#include "stages/ingest/gap_filling.h"

#include <cmath>

namespace syn {
namespace {

// Second derivatives of the natural cubic spline through (x[i], y[i]), by the
// tridiagonal (Thomas) solve. x strictly increasing, n >= 2.
void NaturalSplineSecondDerivatives(const std::vector<double>& x, const std::vector<double>& y,
                                    std::vector<double>& second, std::vector<double>& scratch) {
  const size_t n = x.size();
  second.assign(n, 0.0);
  scratch.assign(n, 0.0);
  for (size_t i = 1; i + 1 < n; ++i) {
    const double sigma = (x[i] - x[i - 1]) / (x[i + 1] - x[i - 1]);
    const double p = sigma * second[i - 1] + 2.0;
    second[i] = (sigma - 1.0) / p;
    const double slope_change = (y[i + 1] - y[i]) / (x[i + 1] - x[i]) - (y[i] - y[i - 1]) / (x[i] - x[i - 1]);
    scratch[i] = (6.0 * slope_change / (x[i + 1] - x[i - 1]) - sigma * scratch[i - 1]) / p;
  }
  second[n - 1] = 0.0;
  for (size_t k = n - 1; k-- > 0;) second[k] = second[k] * second[k + 1] + scratch[k];
}

// Value at t of the spline piece between knots lo and lo+1.
double EvaluatePiece(const std::vector<double>& x, const std::vector<double>& y, const std::vector<double>& second,
                     size_t lo, double t) {
  const double h = x[lo + 1] - x[lo];
  const double a = (x[lo + 1] - t) / h;
  const double b = (t - x[lo]) / h;
  return a * y[lo] + b * y[lo + 1] + ((a * a * a - a) * second[lo] + (b * b * b - b) * second[lo + 1]) * h * h / 6.0;
}

}  // namespace

std::vector<MarkerGapReport> FillMarkerGaps(MarkerData& data, int64_t max_gap_frames) {
  const int64_t frames = data.frame_count();
  const int64_t markers = data.marker_count();
  std::vector<MarkerGapReport> reports(static_cast<size_t>(markers));
  std::vector<double> knot_time, knot_value, second, scratch;
  std::vector<size_t> valid_frames;
  auto at = [&](int64_t frame, int64_t marker, int axis) -> double& {
    return data.points[static_cast<size_t>((frame * markers + marker) * 3 + axis)];
  };
  for (int64_t m = 0; m < markers; ++m) {
    MarkerGapReport& report = reports[static_cast<size_t>(m)];
    valid_frames.clear();
    for (int64_t t = 0; t < frames; ++t) {
      if (std::isfinite(at(t, m, 0)) && std::isfinite(at(t, m, 1)) && std::isfinite(at(t, m, 2))) {
        valid_frames.push_back(static_cast<size_t>(t));
      } else {
        for (int axis = 0; axis < 3; ++axis) at(t, m, axis) = std::nan("");  // a partial sample is missing
      }
    }
    report.missing_before = frames - static_cast<int64_t>(valid_frames.size());
    // Interior gaps: consecutive valid frames more than one apart.
    std::vector<size_t> gaps_to_fill;  // index k into valid_frames: the gap after valid_frames[k]
    for (size_t k = 0; k + 1 < valid_frames.size(); ++k) {
      const int64_t length = static_cast<int64_t>(valid_frames[k + 1] - valid_frames[k]) - 1;
      if (length <= 0) continue;
      ++report.gaps;
      if (length <= max_gap_frames) gaps_to_fill.push_back(k);
    }
    if (!valid_frames.empty()) {
      // Runs at the trial's start or end count as gaps but are never filled.
      report.gaps += (valid_frames.front() > 0) + (valid_frames.back() + 1 < static_cast<size_t>(frames));
    } else if (frames > 0) {
      report.gaps = 1;
    }
    if (!gaps_to_fill.empty()) {
      knot_time.resize(valid_frames.size());
      knot_value.resize(valid_frames.size());
      for (size_t k = 0; k < valid_frames.size(); ++k) knot_time[k] = data.time_s[valid_frames[k]];
      for (int axis = 0; axis < 3; ++axis) {
        for (size_t k = 0; k < valid_frames.size(); ++k) {
          knot_value[k] = at(static_cast<int64_t>(valid_frames[k]), m, axis);
        }
        NaturalSplineSecondDerivatives(knot_time, knot_value, second, scratch);
        for (size_t k : gaps_to_fill) {
          for (size_t t = valid_frames[k] + 1; t < valid_frames[k + 1]; ++t) {
            at(static_cast<int64_t>(t), m, axis) = EvaluatePiece(knot_time, knot_value, second, k, data.time_s[t]);
          }
        }
      }
      for (size_t k : gaps_to_fill) {
        report.missing_after -= static_cast<int64_t>(valid_frames[k + 1] - valid_frames[k] - 1);
      }
      report.gaps_filled = static_cast<int64_t>(gaps_to_fill.size());
    }
    report.missing_after += report.missing_before;
  }
  return reports;
}

}  // namespace syn
