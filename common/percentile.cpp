#include "common/percentile.h"

#include <algorithm>
#include <cmath>

namespace syn {

double NearestRankPercentile(std::vector<double> values, double fraction) {
  values.erase(std::remove_if(values.begin(), values.end(), [](double v) { return !std::isfinite(v); }), values.end());
  if (values.empty()) return std::nan("");
  const size_t index = std::min(values.size() - 1, static_cast<size_t>(fraction * static_cast<double>(values.size() - 1) + 0.5));
  std::nth_element(values.begin(), values.begin() + static_cast<long>(index), values.end());
  return values[index];
}

Spread MedianP95Largest(const std::vector<double>& values) {
  double largest = std::nan("");
  for (const double value : values) {
    if (std::isfinite(value) && !(value <= largest)) largest = value;
  }
  return {NearestRankPercentile(values, 0.5), NearestRankPercentile(values, 0.95), largest};
}

}  // namespace syn
