#include "stages/human/capture_stature.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/error.h"

namespace syn {

CaptureStature StatureFromCapture(const MarkerData& capture, const std::string& file_name) {
  const size_t frames = capture.time_s.size(), markers = capture.labels.size(), bodies = capture.bodies.size();
  for (size_t t = 0; t < frames; ++t) {
    double lowest = std::numeric_limits<double>::infinity(), highest = -lowest;
    int valid = 0;
    auto add = [&](double z) {
      if (!std::isfinite(z)) return;
      lowest = std::min(lowest, z), highest = std::max(highest, z);
      ++valid;
    };
    for (size_t m = 0; m < markers; ++m) add(capture.points[(t * markers + m) * 3 + 2]);
    for (size_t b = 0; b < bodies; ++b) add(capture.body_pose[(t * bodies + b) * 7 + 2]);
    if (valid < 2) continue;
    const double extent = highest - lowest;
    if (!(extent >= 1.0 && extent <= 2.5)) {
      throw DataError(Location::AtFrame(file_name, static_cast<int64_t>(t)),
                      "vertical extent of the capture " + std::to_string(extent) +
                          " m is no adult stature (1-2.5 m): give --height");
    }
    return {extent, static_cast<int64_t>(t)};
  }
  throw DataError(Location::InFile(file_name), "no frame has a valid marker or body position: give --height");
}

}  // namespace syn
