// `*.markers.h5` (schema synsculpt.markers): a capture in SI units, Z up,
// missing samples NaN. Written by syn-ingest, read by syn-retarget.
//
// Datasets: time[T], points[T,M,3], labels[M]; when present computed_points
// [T,K,3] + computed_labels + computed_kinds; bodies[B] + body_parents[B] +
// body_pose[T,B,7] (position, quaternion w,x,y,z), and calibration_body_pose[B,7] when the capture carries
// a calibration stance outside the take (BVH frame 0 under --drop-first-frame); analog[Ta,C] +
// analog_labels + analog_units (root attribute analog_rate_hz);
// event_labels/event_contexts/event_times. Root attributes: rate_hz,
// metadata (JSON: source format, reader facts, ingest conversions, per-marker
// gap_report), warnings (JSON list).
#pragma once

#include <string>

#include "common/intermediate_file.h"
#include "common/marker_data.h"

namespace syn {

inline constexpr const char* kMarkersSchema = "synsculpt.markers";
inline constexpr int64_t kMarkersSchemaVersion = 1;

// Writes `data` into an open writer (the caller made the provenance and commits).
void WriteMarkerData(IntermediateWriter& writer, const MarkerData& data);

// Reads a markers file; refuses another schema or version.
[[nodiscard]] MarkerData ReadMarkersFile(const std::string& path);

}  // namespace syn
