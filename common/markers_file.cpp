#include "common/markers_file.h"

#include "common/error.h"

namespace syn {
namespace {

int64_t Count(const std::vector<std::string>& names) { return static_cast<int64_t>(names.size()); }

}  // namespace

void WriteMarkerData(IntermediateWriter& writer, const MarkerData& data) {
  const int64_t frames = data.frame_count();
  writer.writeDoubles("time", data.time_s);
  writer.writeDoubles("points", {frames, Count(data.labels), 3}, data.points.data());
  writer.writeStrings("labels", data.labels);
  if (!data.computed_labels.empty()) {
    writer.writeDoubles("computed_points", {frames, Count(data.computed_labels), 3}, data.computed_points.data());
    writer.writeStrings("computed_labels", data.computed_labels);
    writer.writeStrings("computed_kinds", data.computed_kinds);
  }
  if (!data.bodies.empty()) {
    writer.writeStrings("bodies", data.bodies);
    writer.writeStrings("body_parents", data.body_parents);
    writer.writeDoubles("body_pose", {frames, Count(data.bodies), 7}, data.body_pose.data());
    if (!data.calibration_body_pose.empty()) {
      writer.writeDoubles("calibration_body_pose", {Count(data.bodies), 7}, data.calibration_body_pose.data());
    }
  }
  if (!data.analog_labels.empty()) {
    const int64_t channels = Count(data.analog_labels);
    writer.writeDoubles("analog", {static_cast<int64_t>(data.analog.size()) / channels, channels},
                        data.analog.data());
    writer.writeStrings("analog_labels", data.analog_labels);
    writer.writeStrings("analog_units", data.analog_units);
    writer.writeAttribute("", "analog_rate_hz", data.analog_rate_hz);
  }
  if (!data.events.empty()) {
    std::vector<std::string> labels, contexts;
    std::vector<double> times;
    for (const CaptureEvent& event : data.events) {
      labels.push_back(event.label);
      contexts.push_back(event.context);
      times.push_back(event.time_s);
    }
    writer.writeStrings("event_labels", labels);
    writer.writeStrings("event_contexts", contexts);
    writer.writeDoubles("event_times", times);
  }
  writer.writeAttribute("", "rate_hz", data.rate_hz);
  writer.writeAttribute("", "metadata", CanonicalJson(data.metadata));
  writer.writeAttribute("", "warnings", CanonicalJson(nlohmann::json(data.warnings)));
}

MarkerData ReadMarkersFile(const std::string& path) {
  IntermediateReader reader(path, kMarkersSchema, kMarkersSchemaVersion);
  MarkerData data;
  data.time_s = reader.readDoubles("time").values;
  data.labels = reader.readStrings("labels");
  data.points = reader.readDoubles("points").values;
  data.rate_hz = reader.readDoubleAttribute("", "rate_hz");
  const size_t frames = data.time_s.size();
  if (data.points.size() != frames * data.labels.size() * 3) {
    throw DataError(Location::InFile(path), "points has " + std::to_string(data.points.size()) +
                                                " values, expected frames x labels x 3");
  }
  if (reader.has("computed_labels")) {
    data.computed_labels = reader.readStrings("computed_labels");
    data.computed_kinds = reader.readStrings("computed_kinds");
    data.computed_points = reader.readDoubles("computed_points").values;
  }
  if (reader.has("bodies")) {
    data.bodies = reader.readStrings("bodies");
    data.body_parents = reader.readStrings("body_parents");
    data.body_pose = reader.readDoubles("body_pose").values;
    if (data.body_pose.size() != frames * data.bodies.size() * 7) {
      throw DataError(Location::InFile(path), "body_pose has the wrong size for frames x bodies x 7");
    }
    if (reader.has("calibration_body_pose")) {
      data.calibration_body_pose = reader.readDoubles("calibration_body_pose").values;
      if (data.calibration_body_pose.size() != data.bodies.size() * 7) {
        throw DataError(Location::InFile(path), "calibration_body_pose has the wrong size for bodies x 7");
      }
    }
  }
  if (reader.has("analog_labels")) {
    data.analog_labels = reader.readStrings("analog_labels");
    data.analog_units = reader.readStrings("analog_units");
    data.analog = reader.readDoubles("analog").values;
    data.analog_rate_hz = reader.readDoubleAttribute("", "analog_rate_hz");
  }
  if (reader.has("event_labels")) {
    const std::vector<std::string> labels = reader.readStrings("event_labels");
    const std::vector<std::string> contexts = reader.readStrings("event_contexts");
    const std::vector<double> times = reader.readDoubles("event_times").values;
    for (size_t i = 0; i < labels.size() && i < contexts.size() && i < times.size(); ++i) {
      data.events.push_back({labels[i], contexts[i], times[i]});
    }
  }
  data.metadata = nlohmann::json::parse(reader.readStringAttribute("", "metadata"));
  for (const auto& warning : nlohmann::json::parse(reader.readStringAttribute("", "warnings"))) {
    data.warnings.push_back(warning.get<std::string>());
  }
  data.length_unit_to_m = 1.0;
  data.up_axis = 'z';
  return data;
}

}  // namespace syn
