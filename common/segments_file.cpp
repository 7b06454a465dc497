#include "common/segments_file.h"

#include "common/error.h"

namespace syn {

void WriteSegmentsData(IntermediateWriter& writer, const SegmentsData& segments) {
  writer.writeDoubles("analysis_time", segments.analysis_time);
  writer.writeDoubles("delta_p", segments.delta_p);
  writer.writeInts("boundaries", segments.boundaries);
  writer.writeStrings("boundary_reasons", segments.reasons);
  writer.writeAttribute("", "threshold_used", segments.threshold_used);
  writer.writeAttribute("", "analysis_rate", segments.analysis_rate);
}

SegmentsData ReadSegmentsFile(const std::string& path) {
  const IntermediateReader reader(path, kSegmentsSchema, kSegmentsSchemaVersion);
  SegmentsData segments;
  segments.analysis_time = reader.readDoubles("analysis_time").values;
  segments.delta_p = reader.readDoubles("delta_p").values;
  segments.boundaries = reader.readInts("boundaries");
  if (reader.has("boundary_reasons")) segments.reasons = reader.readStrings("boundary_reasons");
  segments.threshold_used = reader.readDoubleAttribute("", "threshold_used");
  segments.analysis_rate = reader.readDoubleAttribute("", "analysis_rate");
  if (segments.analysis_time.size() != segments.delta_p.size()) {
    throw DataError(Location::InFile(path), "analysis_time and delta_p differ in length");
  }
  for (size_t i = 1; i < segments.boundaries.size(); ++i) {
    if (segments.boundaries[i] <= segments.boundaries[i - 1]) {
      throw DataError(Location::InFile(path), "boundaries must increase (entry " + std::to_string(i) + ")");
    }
  }
  return segments;
}

}  // namespace syn
