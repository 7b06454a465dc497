// The nearest-rank percentile every figure a user reads is reported with (syn-retarget's summary line,
// syn-release's quality table), so the two agree to the digit.
#pragma once

#include <vector>

namespace syn {

// The value at rank round(fraction × (n − 1)) of the finite entries, sorted; NaN when none is finite.
[[nodiscard]] double NearestRankPercentile(std::vector<double> values, double fraction);

}  // namespace syn
