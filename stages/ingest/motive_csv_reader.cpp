#include "stages/ingest/motive_csv_reader.h"

#include <cmath>
#include <map>

#include <Eigen/Geometry>

#include "common/error.h"
#include "common/file_bytes.h"
#include "stages/ingest/text_fields.h"

namespace syn {
namespace {

// Splits a CSV line, honouring double quotes (IDs are quoted).
void SplitCsv(std::string_view line, std::vector<std::string>& cells) {
  cells.clear();
  std::string cell;
  bool quoted = false;
  for (char c : line) {
    if (c == '"') quoted = !quoted;
    else if (c == ',' && !quoted) cells.push_back(cell), cell.clear();
    else cell += c;
  }
  cells.push_back(cell);
}

double LengthUnit(const std::string& unit) {
  if (unit == "Millimeters") return 0.001;
  if (unit == "Centimeters") return 0.01;
  if (unit == "Meters") return 1.0;
  return 0.0;
}

// One thing the columns describe: a point (X, Y, Z) or a body (position + rotation).
struct Entity {
  bool body = false;
  std::string name;
  int position[3] = {-1, -1, -1};
  int rotation[4] = {-1, -1, -1, -1};  // X, Y, Z, W (quaternion) or X, Y, Z (Euler)
};

}  // namespace

MarkerData ParseMotiveCsv(std::string_view text, const std::string& source_name) {
  LineReader lines(text);
  std::string_view line;
  std::vector<std::string> cells;
  const auto fail = [&](const std::string& message) { return DataError(Location::AtLine(source_name, lines.lineNumber()), message); };
  if (!lines.next(&line)) throw DataError(Location::AtLine(source_name, 1), "empty file");
  if (line.rfind("\xEF\xBB\xBF", 0) == 0) line.remove_prefix(3);
  if (line.rfind("Format Version,", 0) != 0) throw fail("expected a Motive CSV export starting with 'Format Version,'");
  SplitCsv(line, cells);
  std::map<std::string, std::string> info;
  for (size_t i = 0; i + 1 < cells.size(); i += 2) info[cells[i]] = cells[i + 1];
  MarkerData data;
  data.up_axis = 'y';
  data.length_unit_to_m = info.count("Length Units") ? LengthUnit(info["Length Units"]) : 0.001;
  if (data.length_unit_to_m == 0.0) throw fail("Length Units '" + info["Length Units"] + "': expected Millimeters, Centimeters or Meters");
  double rate = 0;
  const std::string rate_text = info.count("Export Frame Rate") ? info["Export Frame Rate"] : info["Capture Frame Rate"];
  if (ParseField(rate_text, &rate) != FieldValue::kNumber || !(rate > 0)) throw fail("no usable Export Frame Rate ('" + rate_text + "')");
  data.rate_hz = rate;
  const std::string rotation_type = info.count("Rotation Type") ? info["Rotation Type"] : "Quaternion";

  // Header rows, until the "Frame,Time..." row.
  std::vector<std::string> types, names, kinds, axes;
  bool header_done = false;
  while (lines.next(&line)) {
    if (Trim(line).empty()) continue;
    SplitCsv(line, cells);
    if (cells.size() >= 2 && cells[0].empty() && cells[1] == "Type") types = cells;
    else if (cells.size() >= 2 && cells[0].empty() && cells[1] == "Name") names = cells;
    else if (cells.size() >= 2 && cells[0].empty() && cells[1] == "ID") continue;
    else if (cells.size() >= 2 && cells[0].empty() && cells[1].empty()) kinds = cells;
    else if (!cells.empty() && cells[0].rfind("Frame", 0) == 0) {
      axes = cells;
      header_done = true;
      break;
    } else {
      throw fail("unexpected header row; expected Type, Name, ID, a data-kind row or 'Frame,Time (Seconds),...'");
    }
  }
  if (!header_done) throw fail("the file ends before the 'Frame,Time (Seconds),...' header row");
  size_t columns = axes.size();
  while (columns > 2 && Trim(axes[columns - 1]).empty()) --columns;
  if (columns <= 2) {
    throw fail("this export has no data columns (only Frame and Time): nothing was selected for export in Motive");
  }
  const auto cell = [](const std::vector<std::string>& row, size_t c) { return c < row.size() ? row[c] : std::string(); };
  std::vector<Entity> entities;
  std::map<std::string, size_t> index_of;
  int unnamed = 0;
  for (size_t c = 2; c < columns; ++c) {
    const std::string type = cell(types, c);
    const std::string kind = cell(kinds, c);
    std::string name = cell(names, c);
    const std::string axis = Trim(axes[c]).empty() ? "" : std::string(1, Trim(axes[c])[0]);
    if (kind == "Mean Marker Error" || kind == "Marker Quality" || kind.find("Error") != std::string::npos) continue;
    if (name.empty()) {
      name = "Column" + std::to_string(c / 3);
      if (unnamed++ == 0) data.warnings.push_back("header cells without names: columns named by position (older export)");
    }
    const bool body = type == "Rigid Body" || type == "Bone";
    const std::string key = (body ? "B:" : "P:") + name;
    if (!index_of.count(key)) {
      index_of[key] = entities.size();
      Entity entity;
      entity.body = body;
      entity.name = name;
      entities.push_back(entity);
    }
    Entity& entity = entities[index_of[key]];
    const int slot = axis == "X" ? 0 : axis == "Y" ? 1 : axis == "Z" ? 2 : axis == "W" ? 3 : -1;
    if (slot < 0) continue;
    if (kind == "Rotation" && body) entity.rotation[slot] = static_cast<int>(c);
    else if (slot < 3 && (kind == "Position" || kind.empty())) entity.position[slot] = static_cast<int>(c);
  }
  for (const Entity& entity : entities) {
    if (entity.body) {
      data.bodies.push_back(entity.name);
      data.body_parents.push_back("");
    } else {
      data.labels.push_back(entity.name);
    }
  }
  if (data.labels.empty() && data.bodies.empty()) throw fail("no marker, rigid body or bone columns found");
  const bool quaternion = rotation_type == "Quaternion";

  // Data rows.
  std::vector<std::string_view> fields;
  std::vector<double> values(columns);
  while (lines.next(&line)) {
    if (Trim(line).empty()) continue;
    SplitFields(line, ',', fields);
    for (size_t c = 0; c < columns; ++c) {
      if (c >= fields.size()) {
        values[c] = std::nan("");
        continue;
      }
      if (ParseField(fields[c], &values[c]) == FieldValue::kInvalid) {
        throw fail("column " + std::to_string(c + 1) + ": '" + std::string(fields[c]) + "' is not a number");
      }
    }
    if (std::isnan(values[1])) throw fail("a data row without a time");
    data.time_s.push_back(values[1]);
    for (const Entity& entity : entities) {
      const auto at = [&](int column) { return column < 0 ? std::nan("") : values[static_cast<size_t>(column)]; };
      const double x = at(entity.position[0]), y = at(entity.position[1]), z = at(entity.position[2]);
      const bool present = !std::isnan(x) && !std::isnan(y) && !std::isnan(z);
      if (!entity.body) {
        data.points.insert(data.points.end(), {present ? x : std::nan(""), present ? y : std::nan(""), present ? z : std::nan("")});
        continue;
      }
      Eigen::Quaterniond orientation(std::nan(""), std::nan(""), std::nan(""), std::nan(""));
      if (quaternion) {
        const double qx = at(entity.rotation[0]), qy = at(entity.rotation[1]), qz = at(entity.rotation[2]), qw = at(entity.rotation[3]);
        if (!std::isnan(qx + qy + qz + qw)) orientation = Eigen::Quaterniond(qw, qx, qy, qz).normalized();
      } else {
        const double angle[3] = {at(entity.rotation[0]), at(entity.rotation[1]), at(entity.rotation[2])};
        if (!std::isnan(angle[0] + angle[1] + angle[2]) && rotation_type.size() == 3) {
          Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
          for (char axis_name : rotation_type) {
            const int axis = axis_name - 'X';
            if (axis < 0 || axis > 2) throw fail("Rotation Type '" + rotation_type + "': expected Quaternion or an order like XYZ");
            rotation = rotation * Eigen::AngleAxisd(angle[axis] * M_PI / 180.0, Eigen::Vector3d::Unit(axis)).toRotationMatrix();
          }
          orientation = Eigen::Quaterniond(rotation);
        }
      }
      data.body_pose.insert(data.body_pose.end(), {present ? x : std::nan(""), present ? y : std::nan(""), present ? z : std::nan(""),
                                                   orientation.w(), orientation.x(), orientation.y(), orientation.z()});
    }
  }
  const std::string exported = info.count("Total Exported Frames") ? info["Total Exported Frames"] : "";
  double declared = 0;
  if (ParseField(exported, &declared) == FieldValue::kNumber && declared != static_cast<double>(data.frame_count())) {
    data.warnings.push_back("Total Exported Frames says " + exported + " but " + std::to_string(data.frame_count()) +
                            " data rows are present");
  }
  data.metadata["motive"] = info;
  return data;
}

MarkerData ReadMotiveCsv(const std::string& path) { return ParseMotiveCsv(ReadFileText(path), path); }

}  // namespace syn
