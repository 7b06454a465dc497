#include "stages/ingest/capture_normalization.h"

#include <cctype>
#include <map>
#include <set>

#include <Eigen/Geometry>

#include "common/text_encoding.h"
#include "stages/ingest/up_axis.h"

namespace syn {
namespace {

// Rotation taking coordinates with `up` vertical to coordinates with Z vertical.
Eigen::Matrix3d UpAxisToZ(char up) {
  Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
  if (up == 'y') rotation << 0, 0, 1, 1, 0, 0, 0, 1, 0;  // (x, y, z) -> (z, x, y)
  if (up == 'x') rotation << 0, 1, 0, 0, 0, 1, 1, 0, 0;  // (x, y, z) -> (y, z, x)
  return rotation;
}

void TransformPositions(std::vector<double>& values, size_t stride, double scale, const Eigen::Matrix3d& rotation) {
  for (size_t i = 0; i + 3 <= values.size(); i += stride) {
    Eigen::Map<Eigen::Vector3d> position(&values[i]);
    position = scale * (rotation * position);
  }
}

void RotateOrientations(std::vector<double>& body_pose, const Eigen::Quaterniond& rotation) {
  for (size_t i = 0; i + 7 <= body_pose.size(); i += 7) {
    const Eigen::Quaterniond old(body_pose[i + 3], body_pose[i + 4], body_pose[i + 5], body_pose[i + 6]);
    const Eigen::Quaterniond rotated = rotation * old;  // NaN stays NaN
    body_pose[i + 3] = rotated.w();
    body_pose[i + 4] = rotated.x();
    body_pose[i + 5] = rotated.y();
    body_pose[i + 6] = rotated.z();
  }
}

std::string StripPrefix(const std::string& label) {
  const size_t colon = label.rfind(':');
  return colon == std::string::npos ? label : label.substr(colon + 1);
}

void MakeUnique(std::vector<std::string>& names, const char* what, std::vector<std::string>& warnings) {
  std::set<std::string> taken(names.begin(), names.end());
  std::map<std::string, int> seen;
  for (std::string& name : names) {
    if (++seen[name] == 1) continue;
    std::string renamed;
    for (int suffix = seen[name];; ++suffix) {
      renamed = name + "_" + std::to_string(suffix);
      if (!taken.count(renamed)) break;
    }
    warnings.push_back(std::string("duplicate ") + what + " '" + name + "' renamed to '" + renamed + "'");
    taken.insert(renamed);
    name = renamed;
  }
}

// Every text the file gave us becomes valid UTF-8 by the one rule of common/text_encoding.h (Latin-1
// decoded, other stray bytes as \xNN), so labels, JSON metadata and HDF5 attributes agree.
void MakeTextUtf8(MarkerData& data) {
  for (std::vector<std::string>* names : {&data.labels, &data.computed_labels, &data.computed_kinds, &data.bodies,
                                          &data.body_parents, &data.analog_labels, &data.analog_units, &data.warnings}) {
    for (std::string& name : *names) name = ToUtf8(name);
  }
  for (CaptureEvent& event : data.events) event.label = ToUtf8(event.label), event.context = ToUtf8(event.context);
  MakeJsonUtf8(data.metadata);
}

}  // namespace

void NormalizeCapture(MarkerData& data, const NormalizationOptions& options) {
  MakeTextUtf8(data);
  const double scale = options.length_unit_to_m > 0 ? options.length_unit_to_m : data.length_unit_to_m;
  char up = options.up_axis;
  std::string up_reason = "--up-axis " + std::string(1, up);
  if (options.up_axis == 'a') {
    const UpAxisDecision decision = DecideUpAxis(data, data.up_axis, scale);
    up = decision.axis;
    up_reason = decision.reason;
    const bool has_convention = data.up_axis == 'x' || data.up_axis == 'y' || data.up_axis == 'z';
    if (decision.from_data && has_convention && decision.axis != data.up_axis) {
      data.warnings.push_back(std::string("the data says ") + static_cast<char>(std::toupper(up)) +
                              " is up, not the format's " + static_cast<char>(std::toupper(data.up_axis)) + " (" +
                              decision.reason + "); using " + static_cast<char>(std::toupper(up)) +
                              " (use --up-axis to override)");
    } else if (!decision.from_data && !has_convention) {
      data.warnings.push_back("neither the file nor the data says which axis is up; assuming Z (use --up-axis to override)");
    }
  }
  const Eigen::Matrix3d rotation = UpAxisToZ(up);
  TransformPositions(data.points, 3, scale, rotation);
  TransformPositions(data.body_pose, 7, scale, rotation);
  RotateOrientations(data.body_pose, Eigen::Quaterniond(rotation));
  TransformPositions(data.calibration_body_pose, 7, scale, rotation);
  RotateOrientations(data.calibration_body_pose, Eigen::Quaterniond(rotation));
  data.metadata["ingest"]["length_unit_to_m"] = scale;
  data.metadata["ingest"]["original_up_axis"] = std::string(1, up);
  data.metadata["ingest"]["up_axis_reason"] = up_reason;
  data.length_unit_to_m = 1.0;
  data.up_axis = 'z';

  if (options.rate_hz > 0) {
    if (data.rate_hz > 0 && data.rate_hz != options.rate_hz) {
      data.warnings.push_back("frame rate " + std::to_string(data.rate_hz) + " Hz in the file overridden by --rate " +
                              std::to_string(options.rate_hz));
    }
    data.metadata["ingest"]["file_rate_hz"] = data.rate_hz;
    data.rate_hz = options.rate_hz;
    for (size_t t = 0; t < data.time_s.size(); ++t) data.time_s[t] = static_cast<double>(t) / data.rate_hz;
  }

  if (options.strip_prefix) {
    for (std::string& label : data.labels) label = StripPrefix(label);
    for (std::string& body : data.bodies) body = StripPrefix(body);
    for (std::string& parent : data.body_parents) parent = StripPrefix(parent);
  }
  MakeUnique(data.labels, "marker label", data.warnings);
  MakeUnique(data.computed_labels, "computed point label", data.warnings);
  MakeUnique(data.bodies, "body name", data.warnings);
}

}  // namespace syn
