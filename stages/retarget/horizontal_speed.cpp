#include "stages/retarget/horizontal_speed.h"

#include <algorithm>
#include <cmath>

namespace syn {

std::vector<double> CentredHorizontalSpeeds(const std::vector<Eigen::Vector3d>& positions,
                                            const std::vector<double>& time_s, double window) {
  const int64_t frames = static_cast<int64_t>(positions.size());
  const double half_window = 0.5 * window;
  std::vector<double> speeds(positions.size(), std::nan(""));
  int64_t before = 0, after = 0;  // window ends, moved along with t
  for (int64_t t = 0; t < frames; ++t) {
    const double now = time_s[static_cast<size_t>(t)];
    while (before < t && time_s[static_cast<size_t>(before)] < now - half_window) ++before;
    if (after < t) after = t;
    while (after + 1 < frames && time_s[static_cast<size_t>(after + 1)] <= now + half_window) ++after;
    const int64_t a = std::min(before, std::max<int64_t>(t - 1, 0)), b = std::max(after, std::min(t + 1, frames - 1));
    const Eigen::Vector3d &pa = positions[static_cast<size_t>(a)], &pb = positions[static_cast<size_t>(b)];
    if (b == a || !positions[static_cast<size_t>(t)].allFinite() || !pa.allFinite() || !pb.allFinite()) continue;
    speeds[static_cast<size_t>(t)] = (pb - pa).head<2>().norm() / (time_s[static_cast<size_t>(b)] - time_s[static_cast<size_t>(a)]);
  }
  return speeds;
}

}  // namespace syn
