#include "stages/human/capture_stature.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/error.h"

namespace syn {

namespace {

// Highest minus lowest finite z over `markers` points (x, y, z) and `bodies` poses (x, y, z, quaternion);
// NaN with fewer than two finite values.
double VerticalExtent(const double* points, size_t markers, const double* poses, size_t bodies) {
  double lowest = std::numeric_limits<double>::infinity(), highest = -lowest;
  int valid = 0;
  auto add = [&](double z) {
    if (!std::isfinite(z)) return;
    lowest = std::min(lowest, z), highest = std::max(highest, z);
    ++valid;
  };
  for (size_t m = 0; m < markers; ++m) add(points[m * 3 + 2]);
  for (size_t b = 0; b < bodies; ++b) add(poses[b * 7 + 2]);
  return valid >= 2 ? highest - lowest : std::nan("");
}

}  // namespace

CaptureStature StatureFromCapture(const MarkerData& capture, const std::string& file_name) {
  const size_t frames = capture.time_s.size(), markers = capture.labels.size(), bodies = capture.bodies.size();
  const auto checked = [&](double extent, int64_t frame) {
    if (!(extent >= 1.0 && extent <= 2.5)) {
      const Location where = frame < 0 ? Location::InFile(file_name) : Location::AtFrame(file_name, frame);
      throw DataError(where, std::string("vertical extent of the capture") + (frame < 0 ? "'s calibration frame " : " ") +
                                 std::to_string(extent) + " m is no adult stature (1-2.5 m): give --height");
    }
    return CaptureStature{extent, frame};
  };
  if (!capture.calibration_body_pose.empty()) {
    const double extent = VerticalExtent(nullptr, 0, capture.calibration_body_pose.data(), bodies);
    if (std::isfinite(extent)) return checked(extent, -1);
  }
  for (size_t t = 0; t < frames; ++t) {
    const double extent = VerticalExtent(capture.points.data() + t * markers * 3, markers,
                                         capture.body_pose.data() + t * bodies * 7, bodies);
    if (std::isfinite(extent)) return checked(extent, static_cast<int64_t>(t));
  }
  throw DataError(Location::InFile(file_name), "no frame has a valid marker or body position: give --height");
}

}  // namespace syn
