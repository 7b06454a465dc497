#include "tools/release/trial_quality.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/file_bytes.h"
#include "common/intermediate_file.h"
#include "common/motion_file.h"
#include "common/percentile.h"

namespace syn {
namespace {

// Root attributes syn-retarget's contact detection writes (issue 17); absent before it.
double OptionalAttribute(const IntermediateReader& reader, const char* name) {
  return reader.hasAttribute("", name) ? reader.readDoubleAttribute("", name) : std::nan("");
}

}  // namespace

TrialQuality ReadTrialQuality(const std::string& motion_path, const std::string& metrics_path,
                              const std::map<std::string, int>& priority_of_landmark) {
  const IntermediateReader reader(motion_path, kMotionSchema, kMotionSchemaVersion);
  TrialQuality quality;
  const DoubleArray time = reader.readDoubles("time");
  quality.frames = static_cast<int64_t>(time.values.size());
  quality.duration_s = quality.frames > 0 ? time.values.back() - time.values.front() : 0.0;
  quality.rate_hz = quality.duration_s > 0 ? static_cast<double>(quality.frames - 1) / quality.duration_s : std::nan("");

  std::vector<double> position[2], angle[2];
  if (reader.has("landmark_error") && reader.has("landmark_names")) {
    const std::vector<std::string> names = reader.readStrings("landmark_names");
    const DoubleArray errors = reader.readDoubles("landmark_error");
    const size_t landmarks = names.size();
    if (errors.dims.size() != 3 || errors.dims[1] != static_cast<int64_t>(landmarks) || errors.dims[2] != 2) {
      throw DataError(Location::InFile(motion_path), "landmark_error is not [T, landmarks, 2]");
    }
    for (size_t i = 0; i < landmarks; ++i) {
      const auto found = priority_of_landmark.find(names[i]);
      const int level = found == priority_of_landmark.end() ? 1 : found->second;
      if (level != 1 && level != 2) continue;
      for (int64_t t = 0; t < errors.dims[0]; ++t) {
        const size_t at = (static_cast<size_t>(t) * landmarks + i) * 2;
        position[level - 1].push_back(errors.values[at] * 1000.0);
        angle[level - 1].push_back(errors.values[at + 1] * 180.0 / M_PI);
      }
    }
  }
  quality.p1_position_median_mm = NearestRankPercentile(position[0], 0.5);
  quality.p1_position_p95_mm = NearestRankPercentile(position[0], 0.95);
  quality.p1_angle_median_deg = NearestRankPercentile(angle[0], 0.5);
  quality.p1_angle_p95_deg = NearestRankPercentile(angle[0], 0.95);
  quality.p2_position_median_mm = NearestRankPercentile(position[1], 0.5);
  quality.p2_position_p95_mm = NearestRankPercentile(position[1], 0.95);
  quality.p2_angle_median_deg = NearestRankPercentile(angle[1], 0.5);
  quality.p2_angle_p95_deg = NearestRankPercentile(angle[1], 0.95);

  quality.stance_drift_median_mm = OptionalAttribute(reader, "stance_drift_median_mm");
  quality.stance_drift_p95_mm = OptionalAttribute(reader, "stance_drift_p95_mm");
  quality.deepest_penetration_mm = OptionalAttribute(reader, "deepest_penetration_mm");
  quality.penetration_frames_ratio = OptionalAttribute(reader, "penetration_frames_ratio");
  if (reader.has("contact_feet")) quality.contact_feet = reader.readStrings("contact_feet");

  quality.foot_sliding_ratio = std::nan("");
  try {
    const nlohmann::json metrics = nlohmann::json::parse(ReadFileText(metrics_path));
    const nlohmann::json* sliding = metrics.contains("trial") ? &metrics["trial"] : nullptr;
    if (sliding && sliding->contains("foot_sliding_ratio") && (*sliding)["foot_sliding_ratio"].is_number()) {
      quality.foot_sliding_ratio = (*sliding)["foot_sliding_ratio"].get<double>();
    }
  } catch (const nlohmann::json::exception& error) {
    throw DataError(Location::InFile(metrics_path), std::string("not valid JSON: ") + error.what());
  }
  return quality;
}

std::string ContactFlagsCsv(const std::string& motion_path) {
  const IntermediateReader reader(motion_path, kMotionSchema, kMotionSchemaVersion);
  if (!reader.has("contact") || !reader.has("contact_feet")) return "";
  const std::vector<std::string> feet = reader.readStrings("contact_feet");
  const std::vector<int64_t> flags = reader.readInts("contact");
  const std::vector<double> time = reader.readDoubles("time").values;
  if (flags.size() != time.size() * feet.size()) {
    throw DataError(Location::InFile(motion_path), "contact holds " + std::to_string(flags.size()) + " flags, expected " +
                                                       std::to_string(time.size()) + " frames x " +
                                                       std::to_string(feet.size()) + " feet");
  }
  std::string csv = "time";
  for (const std::string& foot : feet) csv += "," + foot;
  csv += "\n";
  char number[32];
  for (size_t t = 0; t < time.size(); ++t) {
    std::snprintf(number, sizeof number, "%.17g", time[t]);
    csv += number;
    for (size_t f = 0; f < feet.size(); ++f) csv += flags[t * feet.size() + f] ? ",1" : ",0";
    csv += "\n";
  }
  return csv;
}

std::string FigureText(double value, int decimals) {
  if (!std::isfinite(value)) return "n/a";
  char text[64];
  std::snprintf(text, sizeof text, "%.*f", decimals, value);
  const std::string figure(text);
  // A negative value that rounds to zero prints as "0.0", not "-0.0".
  const bool negative_zero = figure[0] == '-' && figure.find_first_not_of("-0.") == std::string::npos;
  return negative_zero ? figure.substr(1) : figure;
}

}  // namespace syn
