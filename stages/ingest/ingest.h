// syn-ingest: any capture file -> one MarkerData in SI units, Z up.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/marker_data.h"
#include "stages/ingest/gap_filling.h"

namespace syn {

struct IngestOptions {
  // "auto" detects the format from the file's first bytes (DetectCaptureFormat).
  std::string format = "auto";
  // "auto" decides from the data (stages/ingest/up_axis.h: the body's largest extent, the floor where the
  // lowest point stays) and falls back to the format's convention only when the data cannot tell (C3D:
  // POINT:Y_SCREEN, else Z; TRC, Motive CSV, BVH, HumanML3D: Y); a disagreement with the convention is a
  // warning. x / y / z force that axis.
  std::string up_axis = "auto";
  // "auto" trusts the file (C3D POINT:UNITS, TRC Units, Motive Length Units;
  // HumanML3D is metres; BVH has no unit, see bvh_scale).
  std::string units = "auto";
  // Fill interior marker gaps of at most this many frames with a cubic spline; 0 = none.
  int64_t fill_gaps = 0;
  // Override the frame rate the file states (some converters write a wrong one); 0 = keep.
  double rate = 0.0;
  // Remove subject prefixes such as "Male:" from labels.
  bool strip_prefix = false;
  // Metres per BVH unit; "auto" applies the rule of GuessBvhScaleToMetres.
  std::string bvh_scale = "auto";
  // Drop BVH frame 0 (the T-pose / reference frame some converters add).
  bool drop_first_frame = false;

  // True if every field is acceptable; otherwise says which and why.
  bool IsValid(std::string* error) const;
  // Every parameter that affects the output bytes, for the `parameters` attribute.
  nlohmann::json ToJson() const;
};

struct IngestSummary {
  std::string format;
  int64_t frames = 0;
  int64_t markers = 0;
  int64_t bodies = 0;
  int64_t analog_channels = 0;
  double rate_hz = 0.0;
  char up_axis = 'z';             // the file's axis that became +Z
  std::string up_axis_reason;     // why (data cues, the convention, or --up-axis)
  std::vector<MarkerGapReport> gaps;  // per marker
  // BVH --drop-first-frame: the frames taken off the take's start, and how many of them eased in from the
  // calibration frame (bvh_reader.h).
  int64_t dropped_lead_frames = 0;
  int64_t dropped_ease_in_frames = 0;
  int64_t dropped_teleport_frames = 0;  // of those, a lead-in ended by a joint's teleport (bvh_reader.cpp)
  int64_t dropped_held_frames = 0;      // of those, one pose repeated exactly before the take moves

  std::string BriefReport() const;
};

// Reads and normalises one capture; `summary` receives what was found.
[[nodiscard]] MarkerData IngestCapture(const std::string& path, const IngestOptions& options, IngestSummary* summary);

}  // namespace syn
