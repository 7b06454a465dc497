#include "stages/ingest/trc_reader.h"

#include <cmath>
#include <map>

#include "common/error.h"
#include "common/file_bytes.h"
#include "stages/ingest/text_fields.h"

namespace syn {
namespace {

double UnitToMetres(std::string_view unit) {
  if (unit == "mm") return 0.001;
  if (unit == "cm") return 0.01;
  if (unit == "m") return 1.0;
  return 0.0;
}

// The header rows may be tab-separated (with trailing tabs) or padded with spaces.
void SplitHeader(std::string_view line, std::vector<std::string_view>& fields) {
  if (line.find('\t') != std::string_view::npos) {
    SplitFields(line, '\t', fields);
    for (std::string_view& field : fields) field = Trim(field);
    while (!fields.empty() && fields.back().empty()) fields.pop_back();
  } else {
    SplitWhitespace(line, fields);
  }
}

}  // namespace

MarkerData ParseTrc(std::string_view text, const std::string& source_name) {
  LineReader lines(text);
  std::string_view line;
  std::vector<std::string_view> fields, values;
  const auto fail = [&](const std::string& message) -> DataError {
    return DataError(Location::AtLine(source_name, lines.lineNumber()), message);
  };
  const auto need_line = [&](const char* what) {
    if (!lines.next(&line)) throw DataError(Location::AtLine(source_name, lines.lineNumber() + 1),
                                            std::string("the file ends before the ") + what);
  };
  need_line("PathFileType line");
  if (line.rfind("PathFileType", 0) != 0) throw fail("expected a TRC file starting with 'PathFileType'");
  need_line("header key row (DataRate CameraRate NumFrames NumMarkers Units ...)");
  SplitHeader(line, fields);
  std::vector<std::string> keys;
  for (std::string_view key : fields) {
    if (!key.empty()) keys.emplace_back(key);  // a run of tabs is one separator between keys
  }
  need_line("header value row");
  SplitHeader(line, values);
  if (values.size() < keys.size()) throw fail("the header value row has " + std::to_string(values.size()) +
                                              " values for " + std::to_string(keys.size()) + " keys");
  // OpenSim's own examples (Rajagopal 2015) pad the value row with runs of tabs and spaces
  // ("100.0\t\t  100.0\t\t 238\t\t 41\t\t mm"): when the non-empty values alone match the keys one
  // for one, a run of tabs is one separator. Otherwise values stay in their tab columns (an empty value
  // then stays empty).
  std::vector<std::string_view> non_empty;
  for (std::string_view value : values) {
    if (!value.empty()) non_empty.push_back(value);
  }
  if (values.size() != keys.size() && non_empty.size() == keys.size()) values = non_empty;
  std::map<std::string, std::string> header;
  for (size_t i = 0; i < keys.size(); ++i) header[keys[i]] = std::string(values[i]);
  const auto number_of = [&](const char* key, double fallback) {
    const auto found = header.find(key);
    if (found == header.end()) return fallback;
    double value = 0;
    if (ParseField(found->second, &value) != FieldValue::kNumber) {
      throw DataError(Location::AtLine(source_name, 3), std::string(key) + " '" + found->second + "' is not a number");
    }
    return value;
  };
  MarkerData data;
  data.rate_hz = number_of("DataRate", 0.0);
  if (!(data.rate_hz > 0)) throw DataError(Location::AtLine(source_name, 3), "DataRate must be a positive rate in Hz");
  const double declared_frames = number_of("NumFrames", -1);
  const double declared_markers = number_of("NumMarkers", -1);
  // Counts are checked before anything is sized from them: a marker needs at least three characters in
  // some row, so more markers than a third of the file's bytes cannot be real.
  const double most_markers = static_cast<double>(text.size()) / 3.0;
  for (const auto& [key, value] : {std::pair{"NumFrames", declared_frames}, std::pair{"NumMarkers", declared_markers}}) {
    if (value != -1 && (value < 0 || value != std::floor(value) || value > 1e9)) {
      throw DataError(Location::AtLine(source_name, 3), std::string(key) + " must be a whole number of a plausible size");
    }
  }
  if (declared_markers > most_markers) {
    throw DataError(Location::AtLine(source_name, 3), "NumMarkers " + std::to_string(static_cast<int64_t>(declared_markers)) +
                                                          " is more than the file could hold");
  }
  const std::string units = header.count("Units") ? header["Units"] : "mm";
  data.length_unit_to_m = UnitToMetres(units);
  if (data.length_unit_to_m == 0.0) throw DataError(Location::AtLine(source_name, 3), "Units '" + units + "': expected mm, cm or m");
  data.up_axis = 'y';

  // Marker names: columns 2, 5, 8 ... of a tab-separated row (names may hold spaces).
  need_line("marker-name row (Frame# Time NAME ...)");
  if (line.find('\t') != std::string_view::npos) SplitFields(line, '\t', fields);
  else SplitWhitespace(line, fields);
  // Names normally sit every third column; keep a place for each triple, named or not, so a blank name
  // does not shift the ones after it. Some writers space them differently (OpenSim's own TRC export
  // puts two tabs after each name): when the non-empty names alone number NumMarkers, take them in order.
  std::vector<std::string> named;
  for (size_t column = 2; column < fields.size(); ++column) {
    if (!Trim(fields[column]).empty()) named.emplace_back(Trim(fields[column]));
  }
  if (declared_markers >= 0 && named.size() == static_cast<size_t>(declared_markers)) {
    data.labels = named;
  } else {
    for (size_t column = 2; column < fields.size(); column += 3) data.labels.emplace_back(Trim(fields[column]));
  }
  while (!data.labels.empty() && data.labels.back().empty()) data.labels.pop_back();
  if (declared_markers >= 0) {
    const size_t declared = static_cast<size_t>(declared_markers);
    if (declared > data.labels.size()) {
      data.warnings.push_back("NumMarkers says " + std::to_string(declared) + " but only " +
                              std::to_string(data.labels.size()) + " are named; the rest are called Marker<N>");
    }
    data.labels.resize(declared);
  }
  for (size_t m = 0; m < data.labels.size(); ++m) {
    if (data.labels[m].empty()) data.labels[m] = "Marker" + std::to_string(m + 1);
  }
  const size_t markers = data.labels.size();
  // The X1 Y1 Z1 row, which some writers leave out when there are no markers.
  int64_t first_frame_number = -1;
  bool pending = lines.next(&line);
  if (pending && Trim(line).find("X1") != std::string_view::npos) pending = false;
  if (pending && markers == 0 && Trim(line).empty()) pending = false;

  // Reserve what the header promises, but never more than the text could hold (a row needs two bytes per field).
  const size_t frames_possible = text.size() / (2 * (markers * 3 + 2));
  if (declared_frames > 0) {
    const size_t frames = std::min(static_cast<size_t>(declared_frames), frames_possible);
    data.time_s.reserve(frames);
    data.points.reserve(frames * markers * 3);
  }
  while (pending || lines.next(&line)) {
    pending = false;
    if (Trim(line).empty()) continue;
    if (line.find('\t') != std::string_view::npos) SplitFields(line, '\t', fields);
    else SplitWhitespace(line, fields);
    if (fields.size() < 2) throw fail("expected Frame# and Time at the start of a data row");
    double frame_number = 0, time = 0;
    if (ParseField(fields[0], &frame_number) != FieldValue::kNumber) throw fail("Frame# '" + std::string(fields[0]) + "' is not a number");
    if (ParseField(fields[1], &time) != FieldValue::kNumber) throw fail("Time '" + std::string(fields[1]) + "' is not a number");
    if (!(std::abs(frame_number) <= 9.0e15)) throw fail("Frame# '" + std::string(fields[0]) + "' is out of range");
    if (first_frame_number < 0) first_frame_number = static_cast<int64_t>(frame_number);
    // Times increase: a row whose time does not is damaged (a file cut inside "0.01" reads as time 0).
    if (!data.time_s.empty() && !(time > data.time_s.back())) {
      throw fail("Time " + std::string(fields[1]) + " does not increase (previous row: " +
                 std::to_string(data.time_s.back()) + ")");
    }
    data.time_s.push_back(time);
    const size_t base = data.points.size();
    data.points.resize(base + markers * 3, std::nan(""));
    const size_t available = std::min(fields.size() - 2, markers * 3);
    for (size_t i = 0; i < available; ++i) {
      double value = 0;
      if (ParseField(fields[2 + i], &value) == FieldValue::kInvalid) {
        throw fail("marker " + data.labels[i / 3] + " " + "XYZ"[i % 3] + ": '" + std::string(fields[2 + i]) +
                   "' is not a number");
      }
      data.points[base + i] = value;
    }
  }
  // A marker sample with any coordinate missing is missing as a whole.
  for (size_t i = 0; i + 2 < data.points.size(); i += 3) {
    if (std::isnan(data.points[i]) || std::isnan(data.points[i + 1]) || std::isnan(data.points[i + 2])) {
      data.points[i] = data.points[i + 1] = data.points[i + 2] = std::nan("");
    }
  }
  if (declared_frames >= 0 && static_cast<int64_t>(declared_frames) != data.frame_count()) {
    data.warnings.push_back("NumFrames says " + std::to_string(static_cast<int64_t>(declared_frames)) + " but " +
                            std::to_string(data.frame_count()) + " data rows are present");
  }
  data.metadata["trc"] = {{"units", units}, {"first_frame_number", first_frame_number}, {"header", header}};
  return data;
}

MarkerData ReadTrc(const std::string& path) { return ParseTrc(ReadFileText(path), path); }

}  // namespace syn
