// Bringing a capture as read into the frame every later stage assumes
// (DESIGN.md): SI lengths, right-handed, Z up; labels unique.
#pragma once

#include <string>

#include "common/marker_data.h"

namespace syn {

struct NormalizationOptions {
  char up_axis = 'a';              // 'a' = decided from the data (DecideUpAxis), else the reader's convention; or 'x' / 'y' / 'z'
  double length_unit_to_m = 0.0;   // 0 = the file's own unit; else the user's override (mm = 0.001 ...)
  double rate_hz = 0.0;            // 0 = the file's rate; else the user's override (times recomputed)
  bool strip_prefix = false;       // "Male:LFHD" -> "LFHD"
};

// Makes every text (labels, units, events, metadata) valid UTF-8 (common/text_encoding.h), scales marker and body positions to metres, rotates points and body poses
// so the up axis becomes +Z (a cyclic axis permutation, so handedness is kept:
// Y up maps (x, y, z) to (z, x, y)), optionally strips subject prefixes, and
// renames duplicate labels "NAME", "NAME" to "NAME", "NAME_2" with a warning
// (a label is not a unique key in C3D). Records what it did in metadata.
void NormalizeCapture(MarkerData& data, const NormalizationOptions& options);

}  // namespace syn
