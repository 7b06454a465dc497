// The subject's stature from a capture, for syn-human --height-from-markers.
#pragma once

#include <string>

#include "common/marker_data.h"

namespace syn {

struct CaptureStature {
  double height = 0;  // m
  int64_t frame = 0;  // the frame it was measured at; -1: the calibration frame
};

// The vertical extent (highest minus lowest z) of every valid body position in the capture's calibration
// frame (a BVH's T-pose kept aside by syn-ingest --drop-first-frame: standing straight) when it has one;
// otherwise of every valid marker and body position at the first frame that has any: the reference frame
// syn-retarget uses when every landmark is present there. Skeleton
// captures (BVH) carry the head's and toes' end sites, so the extent runs from the top of the head to the
// toe tips; marker captures from the head markers to the foot markers (a marker radius above the floor
// each). At a walking frame it reads a few per cent short of standing stature (measured on CMU walks: see
// README). Throws DataError naming the file and frame when no frame has data or the extent is no adult
// stature (outside 1-2.5 m).
[[nodiscard]] CaptureStature StatureFromCapture(const MarkerData& capture, const std::string& file_name);

}  // namespace syn
