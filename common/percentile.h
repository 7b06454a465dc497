// The nearest-rank percentile every figure a user reads is reported with (syn-retarget's summary line,
// syn-release's quality table), so the two agree to the digit.
#pragma once

#include <vector>

namespace syn {

// The value at rank round(fraction × (n − 1)) of the finite entries, sorted; NaN when none is finite.
[[nodiscard]] double NearestRankPercentile(std::vector<double> values, double fraction);

// How the stages summarise a per-event measure for a user: its median and 95th percentile (nearest rank, as
// above) and its largest finite entry; NaN each when none is finite.
struct Spread {
  double median, p95, largest;
};
[[nodiscard]] Spread MedianP95Largest(const std::vector<double>& values);

}  // namespace syn
