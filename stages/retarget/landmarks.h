// Landmark pose trajectories computed from a capture with a marker set.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "common/marker_data.h"
#include "common/marker_set.h"

namespace syn {

struct LandmarkTrajectories {
  std::vector<std::string> names;       // [L], in the marker set's order
  std::vector<bool> has_orientation;    // [L]; false = position only (orientation NaN)
  std::vector<std::string> sources;     // [L], which capture labels or bodies were used
  std::vector<double> pose;             // [T, L, 7]: position (m) + quaternion (w,x,y,z); NaN = missing
  int64_t frames = 0;

  int64_t count() const { return static_cast<int64_t>(names.size()); }
};

// One landmark in one frame. Missing (NaN position): valid = false. Position only: orientation identity.
struct LandmarkSample {
  bool valid = false;
  bool has_orientation = false;
  Eigen::Vector3d position = Eigen::Vector3d::Zero();
  Eigen::Quaterniond orientation = Eigen::Quaterniond::Identity();
};

[[nodiscard]] LandmarkSample SampleAt(const LandmarkTrajectories& landmarks, int64_t frame, int64_t landmark);

// Resolves every point and body name of `set` against the capture once, then
// builds each landmark's pose per frame. A landmark any of whose points is
// missing in a frame (or whose axes are degenerate, e.g. collinear markers) is
// missing in that frame: NaN, never zero. A name the capture does not have is
// a DataError at the marker set's line that lists the labels the capture has.
[[nodiscard]] LandmarkTrajectories ComputeLandmarks(const MarkerData& capture, const MarkerSet& set,
                                                    const std::string& capture_name);

}  // namespace syn
