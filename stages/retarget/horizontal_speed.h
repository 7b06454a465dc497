// How fast a landmark moves over the floor, frame by frame: what contact detection and the floor fit call
// standing still.
#pragma once

#include <vector>

#include <Eigen/Core>

namespace syn {

// Each sample's horizontal speed (m/s) over a centred window of `window` seconds, widened to at least one
// frame on each side so that it is a centred difference even at low frame rates. NaN where the sample, or
// the sample at either end of its window, is missing (NaN), and for a single frame.
[[nodiscard]] std::vector<double> CentredHorizontalSpeeds(const std::vector<Eigen::Vector3d>& positions,
                                                          const std::vector<double>& time_s, double window);

}  // namespace syn
