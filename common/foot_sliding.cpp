#include "common/foot_sliding.h"

#include <algorithm>
#include <cmath>

namespace syn {

std::vector<uint8_t> FindSlidingFrames(const std::vector<std::vector<FootSample>>& feet, double dt,
                                       const FootSlidingOptions& options) {
  const int64_t frames = feet.empty() ? 0 : static_cast<int64_t>(feet.front().size());
  std::vector<uint8_t> sliding(static_cast<size_t>(frames), 0);
  // Half-window in frames; at least one so that the speed is a difference at all.
  const int64_t half = std::max<int64_t>(1, std::llround(0.5 * options.window / dt));
  for (const std::vector<FootSample>& foot : feet) {
    for (int64_t k = 0; k < frames; ++k) {
      const FootSample& here = foot[static_cast<size_t>(k)];
      if (here.lowest_z < -options.penetration) {
        sliding[static_cast<size_t>(k)] = 1;
        continue;
      }
      if (here.lowest_z >= options.contact_height || frames < 2) continue;
      const int64_t before = std::max<int64_t>(0, k - half), after = std::min(frames - 1, k + half);
      const FootSample& a = foot[static_cast<size_t>(before)];
      const FootSample& b = foot[static_cast<size_t>(after)];
      const double speed = std::hypot(b.x - a.x, b.y - a.y) / (static_cast<double>(after - before) * dt);
      if (speed > options.slide_speed) sliding[static_cast<size_t>(k)] = 1;
    }
  }
  return sliding;
}

}  // namespace syn
