#include "stages/retarget/terrain_flattening.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

#include "common/percentile.h"

namespace syn {
namespace {

// A foot's landmark height above the capture's ground per frame (NaN where missing).
std::vector<double> Heights(const FootContacts& contacts, int64_t landmark, const LandmarkTrajectories& landmarks) {
  std::vector<double> heights(static_cast<size_t>(landmarks.frames));
  for (int64_t t = 0; t < landmarks.frames; ++t) {
    heights[static_cast<size_t>(t)] = SampleAt(landmarks, t, landmark).position.z() - contacts.ground;
  }
  return heights;
}

// A knot of a foot's level: at `frame` the ground under it is `level` m above the capture's ground.
struct Knot {
  int64_t frame;
  double level;
};

// The foot's ground level per frame, as the header describes.
std::vector<double> FootLevels(const FootContacts& contacts, int foot, const std::vector<double>& heights, double band,
                               TerrainFlattening& flattening) {
  const int64_t frames = static_cast<int64_t>(heights.size());
  std::vector<Knot> knots;
  for (const ContactPhase& phase : contacts.phases) {
    if (phase.foot != foot) continue;
    // NaN (no finite height in the phase) is not above the band: on the floor.
    const double median = NearestRankPercentile({heights.begin() + phase.begin, heights.begin() + phase.end}, 0.5);
    const double level = median > band ? median : 0.0;
    if (level > 0) ++flattening.raised_phases, flattening.highest = std::max(flattening.highest, level);
    knots.push_back({phase.begin, level});
    knots.push_back({phase.end - 1, level});
  }
  std::vector<double> levels(static_cast<size_t>(frames), 0.0);
  if (knots.empty() || frames == 0) return levels;
  // The take's ends: on the floor where the foot is within the band there, else on its nearest plant's level.
  const auto end_level = [&](int64_t frame, double nearest) {
    const double height = heights[static_cast<size_t>(frame)];
    return std::isfinite(height) && height < band ? 0.0 : nearest;
  };
  if (knots.front().frame > 0) knots.insert(knots.begin(), {0, end_level(0, knots.front().level)});
  if (knots.back().frame < frames - 1) knots.push_back({frames - 1, end_level(frames - 1, knots.back().level)});
  for (size_t k = 0; k + 1 < knots.size(); ++k) {
    const Knot& a = knots[k];
    const Knot& b = knots[k + 1];
    for (int64_t t = a.frame; t <= b.frame; ++t) {
      const double s = b.frame > a.frame ? static_cast<double>(t - a.frame) / static_cast<double>(b.frame - a.frame) : 0.0;
      levels[static_cast<size_t>(t)] = (1 - s) * a.level + s * b.level;
    }
  }
  return levels;
}

}  // namespace

TerrainFlattening FlattenTerrain(const FootContacts& contacts, const std::vector<int64_t>& foot_landmarks, double band,
                                 LandmarkTrajectories& landmarks) {
  TerrainFlattening flattening;
  const size_t frames = static_cast<size_t>(landmarks.frames);
  std::vector<std::vector<double>> foot_levels;
  for (int f = 0; f < contacts.feet && static_cast<size_t>(f) < foot_landmarks.size(); ++f) {
    if (foot_landmarks[static_cast<size_t>(f)] < 0) {
      foot_levels.emplace_back();
      continue;
    }
    foot_levels.push_back(FootLevels(contacts, f, Heights(contacts, foot_landmarks[static_cast<size_t>(f)], landmarks), band, flattening));
  }
  if (flattening.raised_phases == 0) return flattening;
  std::vector<double> body(frames, 0.0);
  int measured = 0;
  for (const std::vector<double>& levels : foot_levels) {
    if (levels.empty()) continue;
    ++measured;
    for (size_t t = 0; t < frames; ++t) body[t] += levels[t];
  }
  for (double& level : body) level /= measured;
  for (int64_t landmark = 0; landmark < landmarks.count(); ++landmark) {
    const std::vector<double>* offset = &body;
    for (size_t f = 0; f < foot_levels.size(); ++f) {
      if (foot_landmarks[f] == landmark && !foot_levels[f].empty()) offset = &foot_levels[f];
    }
    for (size_t t = 0; t < frames; ++t) {
      landmarks.pose[(t * static_cast<size_t>(landmarks.count()) + static_cast<size_t>(landmark)) * 7 + 2] -= (*offset)[t];
    }
  }
  return flattening;
}

std::string TerrainFlatteningNote(const TerrainFlattening& flattening) {
  if (flattening.raised_phases == 0) return "";
  char text[200];
  std::snprintf(text, sizeof text,
                "uneven terrain: %lld contact phase(s) on raised ground (up to %.0f mm) lowered onto the robot's flat floor, "
                "the body with them",
                static_cast<long long>(flattening.raised_phases), flattening.highest * 1000);
  return text;
}

}  // namespace syn
