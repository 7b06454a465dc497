// Which axis of a capture points up, decided from the data itself.
//
// Two cues, each from every frame's markers and body/joint positions:
//   extent  the body is taller than it is wide or deep: the median over frames of each axis's extent
//           (highest minus lowest point) is largest along the vertical. Decisive when the largest is at
//           least kExtentRatio times the second and at least kMinBodyExtentM (a body, not a few points).
//   floor   the lowest point (the feet, or the body on the floor) stays at floor height while the subject
//           travels: the spread (10th to 90th percentile over frames) of each axis's per-frame minimum is
//           smallest along the vertical. Decisive when that spread is floor-flat (<= kFloorFlatM), the
//           second smallest is at least kFloorRatio times it, and the subject travels (second spread >=
//           kFloorTravelM). Walking in one direction leaves the sideways axis nearly as flat as the
//           vertical, and marker gaps lift the lowest point: both make the cue undecided, not wrong.
// Both decisive and agreeing, or only one decisive: that axis. Both decisive and disagreeing (lying,
// rolling on the floor), or neither (a static pose in place, too few points): the format's convention.
#pragma once

#include <string>

#include "common/marker_data.h"

namespace syn {

inline constexpr double kExtentRatio = 1.25;   // standing adults: height / shoulder width ~ 3; a T-pose ~ 1.0
inline constexpr double kMinBodyExtentM = 0.5;  // a child's sitting height; below it the points are no body
inline constexpr double kFloorRatio = 3.0;
inline constexpr double kFloorFlatM = 0.10;    // feet (or a lying body) on the floor: a few centimetres
inline constexpr double kFloorTravelM = 0.5;   // half a metre of travel before the floor cue counts
inline constexpr int64_t kUpAxisMinFrames = 1;
inline constexpr int64_t kUpAxisMinPoints = 3;  // per frame, to have an extent at all

struct UpAxisDecision {
  char axis = 'z';            // 'x', 'y' or 'z'
  bool from_data = false;     // false: the format's convention (or Z when it has none)
  std::string reason;         // for the summary line, e.g. "data: extent 1.71 m vs 0.52 m; floor agrees"
};

// `convention` is what the reader says ('x', 'y', 'z', or '?' for nothing); `unit_to_m` scales the
// file's lengths to metres (for the travel threshold and the reason text).
[[nodiscard]] UpAxisDecision DecideUpAxis(const MarkerData& data, char convention, double unit_to_m);

}  // namespace syn
