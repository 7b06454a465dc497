// `*.segments.h5` (schema synsculpt.segments): where a motion splits into
// primitives. Written by syn-segment; read by syn-synergies and the report.
//
// Datasets: analysis_time[Ta] (s), delta_p[Ta] (ΔP at each analysis sample, 0
// at the first), boundaries[S+1] (frame indices into the motion: 0, ..., T),
// boundary_reasons[S+1]; attributes threshold_used, analysis_rate (Hz).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "common/intermediate_file.h"

namespace syn {

inline constexpr const char* kSegmentsSchema = "synsculpt.segments";
inline constexpr int64_t kSegmentsSchemaVersion = 1;

struct SegmentsData {
  std::vector<double> analysis_time;     // [Ta] s
  std::vector<double> delta_p;           // [Ta]
  std::vector<int64_t> boundaries;       // [S+1]
  std::vector<std::string> reasons;      // [S+1] why each boundary was placed
  double threshold_used = 0.0;
  double analysis_rate = 0.0;            // Hz
};

void WriteSegmentsData(IntermediateWriter& writer, const SegmentsData& segments);

// Reads a segments file, checking schema, version and that the boundaries increase.
[[nodiscard]] SegmentsData ReadSegmentsFile(const std::string& path);

}  // namespace syn
