#include "stages/retarget/landmarks.h"

#include <algorithm>
#include <cctype>
#include <cmath>

#include <Eigen/Geometry>

#include "common/error.h"

namespace syn {
namespace {

// A point of the capture: a marker (points array) or a body's position.
struct PointSource {
  bool from_body = false;
  int64_t index = -1;
};

std::string MatchKey(const std::string& label) {
  const size_t colon = label.rfind(':');
  std::string key = colon == std::string::npos ? label : label.substr(colon + 1);
  std::transform(key.begin(), key.end(), key.begin(), [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  return key;
}

std::string Joined(const PointChoice& choice) {
  std::string text;
  for (const std::string& name : choice) text += (text.empty() ? "" : "|") + name;
  return text;
}

class PointResolver {
 public:
  PointResolver(const MarkerData& capture, const MarkerSet& set, std::string capture_name)
      : capture_(capture), set_(set), capture_name_(std::move(capture_name)) {}

  // The first alternative the capture has; labels before bodies.
  PointSource resolve(const PointChoice& choice, int line, std::string* used) const {
    for (const std::string& name : choice) {
      const std::string key = MatchKey(name);
      const int64_t label = find(capture_.labels, key, line);
      if (label >= 0) {
        *used = capture_.labels[static_cast<size_t>(label)];
        return {false, label};
      }
      const int64_t body = find(capture_.bodies, key, line);
      if (body >= 0) {
        *used = capture_.bodies[static_cast<size_t>(body)];
        return {true, body};
      }
    }
    throw DataError(Location::AtLine(set_.file, line),
                    "marker set '" + set_.name + "' needs '" + Joined(choice) + "', which " + capture_name_ +
                        " does not have. Its labels: " + list(capture_.labels) + "; its bodies: " +
                        list(capture_.bodies));
  }

  int64_t resolveBody(const PointChoice& choice, int line, std::string* used) const {
    for (const std::string& name : choice) {
      const int64_t body = find(capture_.bodies, MatchKey(name), line);
      if (body >= 0) {
        *used = capture_.bodies[static_cast<size_t>(body)];
        return body;
      }
    }
    throw DataError(Location::AtLine(set_.file, line), "marker set '" + set_.name + "' needs body '" + Joined(choice) +
                                                           "', which " + capture_name_ +
                                                           " does not have. Its bodies: " + list(capture_.bodies));
  }

 private:
  int64_t find(const std::vector<std::string>& names, const std::string& key, int line) const {
    int64_t found = -1;
    for (size_t i = 0; i < names.size(); ++i) {
      if (MatchKey(names[i]) != key) continue;
      if (found >= 0) {
        throw DataError(Location::AtLine(set_.file, line),
                        "'" + key + "' matches both '" + names[static_cast<size_t>(found)] + "' and '" + names[i] +
                            "' in " + capture_name_ + " (several subjects?); ingest one subject per trial");
      }
      found = static_cast<int64_t>(i);
    }
    return found;
  }

  static std::string list(const std::vector<std::string>& names) {
    if (names.empty()) return "(none)";
    std::string text;
    for (const std::string& name : names) text += (text.empty() ? "" : ", ") + name;
    return text;
  }

  const MarkerData& capture_;
  const MarkerSet& set_;
  std::string capture_name_;
};

Eigen::Vector3d PointAt(const MarkerData& capture, const PointSource& source, int64_t frame) {
  if (source.from_body) {
    const double* pose = &capture.body_pose[static_cast<size_t>((frame * static_cast<int64_t>(capture.bodies.size()) +
                                                                 source.index) * 7)];
    return {pose[0], pose[1], pose[2]};
  }
  const double* point =
      &capture.points[static_cast<size_t>((frame * capture.marker_count() + source.index) * 3)];
  return {point[0], point[1], point[2]};
}

Eigen::Vector3d MeanAt(const MarkerData& capture, const std::vector<PointSource>& sources, int64_t frame) {
  Eigen::Vector3d sum = Eigen::Vector3d::Zero();
  for (const PointSource& source : sources) sum += PointAt(capture, source, frame);  // NaN propagates
  return sum / static_cast<double>(sources.size());
}

int AxisIndex(char axis) { return axis - 'x'; }

// Everything a landmark needs per frame, resolved once.
struct ResolvedLandmark {
  int64_t body = -1;
  std::vector<PointSource> origin;
  std::vector<std::vector<PointSource>> axis_from, axis_to;
  std::vector<char> axis_letter;
};

}  // namespace

LandmarkTrajectories ComputeLandmarks(const MarkerData& capture, const MarkerSet& set,
                                      const std::string& capture_name) {
  const PointResolver resolver(capture, set, capture_name);
  LandmarkTrajectories result;
  std::vector<ResolvedLandmark> resolved;
  for (const LandmarkDefinition& definition : set.landmarks) {
    ResolvedLandmark landmark;
    std::string used, sources;
    auto resolveAll = [&](const std::vector<PointChoice>& choices) {
      std::vector<PointSource> points;
      for (const PointChoice& choice : choices) {
        points.push_back(resolver.resolve(choice, definition.line, &used));
        if (sources.find(used) == std::string::npos) sources += (sources.empty() ? "" : " ") + used;
      }
      return points;
    };
    if (!definition.body.empty()) {
      landmark.body = resolver.resolveBody(definition.body, definition.line, &used);
      sources = "body " + used;
    } else {
      landmark.origin = resolveAll(definition.origin);
      for (const AxisDefinition& axis : definition.axes) {
        landmark.axis_from.push_back(resolveAll(axis.from));
        landmark.axis_to.push_back(resolveAll(axis.to));
        landmark.axis_letter.push_back(axis.axis);
      }
    }
    const bool body_has_orientation = landmark.body >= 0;
    result.names.push_back(definition.name);
    result.has_orientation.push_back(body_has_orientation || definition.axes.size() == 2);
    result.sources.push_back(sources);
    resolved.push_back(std::move(landmark));
  }

  const int64_t frames = capture.frame_count();
  const int64_t count = result.count();
  const int64_t bodies = static_cast<int64_t>(capture.bodies.size());
  result.frames = frames;
  result.pose.assign(static_cast<size_t>(frames * count * 7), std::nan(""));
  for (int64_t t = 0; t < frames; ++t) {
    for (int64_t l = 0; l < count; ++l) {
      const ResolvedLandmark& landmark = resolved[static_cast<size_t>(l)];
      double* pose = &result.pose[static_cast<size_t>((t * count + l) * 7)];
      if (landmark.body >= 0) {
        const double* source = &capture.body_pose[static_cast<size_t>((t * bodies + landmark.body) * 7)];
        std::copy(source, source + 7, pose);
        continue;
      }
      const Eigen::Vector3d origin = MeanAt(capture, landmark.origin, t);
      if (!origin.allFinite()) continue;
      if (landmark.axis_letter.empty()) {
        pose[0] = origin.x(), pose[1] = origin.y(), pose[2] = origin.z();
        continue;
      }
      // Gram–Schmidt: the primary axis keeps its direction, the secondary is
      // made orthogonal to it, the third completes a right-handed frame.
      const Eigen::Vector3d primary = MeanAt(capture, landmark.axis_to[0], t) - MeanAt(capture, landmark.axis_from[0], t);
      const Eigen::Vector3d secondary_raw =
          MeanAt(capture, landmark.axis_to[1], t) - MeanAt(capture, landmark.axis_from[1], t);
      if (!primary.allFinite() || !secondary_raw.allFinite() || primary.norm() < 1e-9) continue;
      const Eigen::Vector3d e1 = primary.normalized();
      const Eigen::Vector3d secondary = secondary_raw - secondary_raw.dot(e1) * e1;
      if (secondary.norm() < 1e-6 * secondary_raw.norm() || secondary.norm() < 1e-9) continue;  // collinear
      Eigen::Matrix3d rotation;
      const int first = AxisIndex(landmark.axis_letter[0]);
      const int second = AxisIndex(landmark.axis_letter[1]);
      const int third = 3 - first - second;
      rotation.col(first) = e1;
      rotation.col(second) = secondary.normalized();
      rotation.col(third) = rotation.col((third + 1) % 3).cross(rotation.col((third + 2) % 3));
      const Eigen::Quaterniond q(rotation);
      pose[0] = origin.x(), pose[1] = origin.y(), pose[2] = origin.z();
      pose[3] = q.w(), pose[4] = q.x(), pose[5] = q.y(), pose[6] = q.z();
    }
  }
  return result;
}

LandmarkSample SampleAt(const LandmarkTrajectories& landmarks, int64_t frame, int64_t landmark) {
  const double* pose = &landmarks.pose[static_cast<size_t>((frame * landmarks.count() + landmark) * 7)];
  LandmarkSample sample;
  sample.position = Eigen::Vector3d(pose[0], pose[1], pose[2]);
  sample.valid = sample.position.allFinite();
  sample.has_orientation = std::isfinite(pose[3]) && landmarks.has_orientation[static_cast<size_t>(landmark)];
  sample.orientation = sample.has_orientation ? Eigen::Quaterniond(pose[3], pose[4], pose[5], pose[6]).normalized()
                                              : Eigen::Quaterniond::Identity();
  return sample;
}

}  // namespace syn
