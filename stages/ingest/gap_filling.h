// Filling short marker gaps (`syn-ingest --fill-gaps N`).
#pragma once

#include <cstdint>
#include <vector>

#include "common/marker_data.h"

namespace syn {

struct MarkerGapReport {
  int64_t gaps = 0;             // runs of missing frames between valid ones, before filling
  int64_t gaps_filled = 0;      // runs of at most N frames that were filled
  int64_t missing_before = 0;   // missing samples (frames) before filling, edges included
  int64_t missing_after = 0;    // missing samples left
};

// Fills every interior run of at most `max_gap_frames` missing frames of each
// marker with a natural cubic spline through all of that marker's valid
// samples (knots at the sample times). Longer runs, and runs at the start or
// end of the trial, stay NaN: extrapolating a marker is guessing. With
// max_gap_frames = 0 nothing is filled, but the report is still computed.
// Returns one report per marker.
std::vector<MarkerGapReport> FillMarkerGaps(MarkerData& data, int64_t max_gap_frames);

}  // namespace syn
