// The in-memory form of a capture: what every ingest reader produces and what
// `*.markers.h5` stores (schema `synsculpt.markers`, see common/markers_file.h).
//
// Arrays are row-major, frame first, float64, and a missing sample is NaN —
// never zero. Readers fill it in the file's own units and axes and say which
// (`length_unit_to_m`, `up_axis`); syn-ingest then converts to SI, Z up.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace syn {

struct CaptureEvent {
  std::string label;
  std::string context;  // e.g. "Left", "Right", "General"; empty if the format has none
  double time_s = 0.0;
};

struct MarkerData {
  // Point (marker) trajectories: points[(t * labels.size() + m) * 3 + axis].
  double rate_hz = 0.0;
  std::vector<double> time_s;           // [T]
  std::vector<std::string> labels;      // [M]
  std::vector<double> points;           // [T, M, 3]

  // Derived points some writers store next to markers (C3D POINT:ANGLES,
  // FORCES, MOMENTS, POWERS ...). Not markers: never used as landmarks.
  std::vector<std::string> computed_labels;  // [K]
  std::vector<std::string> computed_kinds;   // [K] "angle", "force", "moment", "power", "scalar", ...
  std::vector<double> computed_points;       // [T, K, 3]

  // Rigid bodies, skeleton bones or joints: position (x,y,z) + quaternion
  // (w,x,y,z) in the capture frame. Orientation NaN where unknown (joints).
  std::vector<std::string> bodies;     // [B]
  std::vector<std::string> body_parents;  // [B] parent body name, "" for roots / unknown
  std::vector<double> body_pose;       // [T, B, 7]
  // The capture's calibration stance, when the file has one that is not part of the take (BVH frame 0 that
  // --drop-first-frame drops: CMU's T-pose): the bodies' poses in it, [B, 7]; empty when there is none.
  // Retargeting onto a map whose reference stance is that pose uses it as the reference frame.
  std::vector<double> calibration_body_pose;

  // Analog channels (force plates, EMG) at their own rate, scaled to physical units.
  double analog_rate_hz = 0.0;
  std::vector<std::string> analog_labels;  // [C]
  std::vector<std::string> analog_units;   // [C]
  std::vector<double> analog;              // [Ta, C]

  std::vector<CaptureEvent> events;

  // How to reach SI and Z-up: multiply lengths by length_unit_to_m; up_axis is
  // 'x', 'y', 'z' or '?' when the file does not say.
  double length_unit_to_m = 1.0;
  char up_axis = '?';

  // Format-specific facts worth keeping (source software, force-plate
  // parameters, C3D processor type, BVH channel layout ...). Stored as JSON.
  nlohmann::json metadata = nlohmann::json::object();

  // Things the reader recovered from (truncated data, duplicate labels ...).
  std::vector<std::string> warnings;

  int64_t frame_count() const { return static_cast<int64_t>(time_s.size()); }
  int64_t marker_count() const { return static_cast<int64_t>(labels.size()); }
};

}  // namespace syn
