#include "stages/retarget/contact_detection.h"

#include <algorithm>
#include <cmath>

#include "stages/retarget/horizontal_speed.h"

namespace syn {

bool ContactDetectionOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& message) {
    if (error) *error = message;
    return false;
  };
  if (!(height >= 0)) return fail("--contact-height must be >= 0 (m)");
  if (!(speed >= 0)) return fail("--contact-speed must be >= 0 (m/s)");
  if (!(release >= 1)) return fail("--contact-release must be >= 1");
  if (!(min_duration >= 0)) return fail("--contact-min-duration must be >= 0 (s)");
  if (!(ground_percentile >= 0 && ground_percentile <= 1)) return fail("contact ground percentile must be in [0, 1]");
  if (!(speed_window > 0)) return fail("contact speed window must be > 0 (s)");
  return true;
}

int64_t FootContacts::framesInContact(int foot) const {
  int64_t count = 0;
  for (int64_t t = 0; t < frames; ++t) count += at(t, foot);
  return count;
}

FootContacts DetectContacts(const std::vector<std::vector<Eigen::Vector3d>>& foot_positions,
                            const std::vector<double>& time_s, const ContactDetectionOptions& options) {
  FootContacts result;
  result.frames = static_cast<int64_t>(time_s.size());
  result.feet = static_cast<int>(foot_positions.size());
  result.contact.assign(static_cast<size_t>(result.frames * result.feet), 0);
  // The ground: a low percentile of every foot height (missing samples left out).
  std::vector<double> heights;
  for (const auto& foot : foot_positions) {
    for (const Eigen::Vector3d& p : foot) {
      if (p.allFinite()) heights.push_back(p.z());
    }
  }
  if (heights.empty() || result.frames == 0) return result;
  const size_t index = std::min(heights.size() - 1, static_cast<size_t>(options.ground_percentile * static_cast<double>(heights.size() - 1)));
  std::nth_element(heights.begin(), heights.begin() + static_cast<long>(index), heights.end());
  result.ground = heights[index];

  const int64_t frames = result.frames;
  for (int f = 0; f < result.feet; ++f) {
    const std::vector<Eigen::Vector3d>& p = foot_positions[static_cast<size_t>(f)];
    const std::vector<double> speeds = CentredHorizontalSpeeds(p, time_s, options.speed_window);
    bool planted = false;
    for (int64_t t = 0; t < frames; ++t) {
      const Eigen::Vector3d& here = p[static_cast<size_t>(t)];
      const double speed = speeds[static_cast<size_t>(t)];
      if (std::isnan(speed)) {  // the foot or a window end missing
        planted = false;
        continue;
      }
      const double height = here.z() - result.ground;
      const double scale = planted ? options.release : 1.0;
      planted = height <= options.height * scale && speed <= options.speed * scale;
      result.contact[static_cast<size_t>(t * result.feet + f)] = planted;
    }
    // Phases, dropping the short ones.
    int64_t t = 0;
    while (t < frames) {
      if (!result.at(t, f)) {
        ++t;
        continue;
      }
      int64_t end = t;
      while (end < frames && result.at(end, f)) ++end;
      const double duration = time_s[static_cast<size_t>(end - 1)] - time_s[static_cast<size_t>(t)];
      // A phase cut by the recording's first or last frame lasted longer than what was captured of it:
      // kept whatever its length (CMU 02_01 starts with 9 frames of a stance, and with it dropped the
      // robot's foot hung 2 cm above the floor there).
      const bool cut_by_recording = t == 0 || end == frames;
      if (!cut_by_recording && duration + 1e-9 < options.min_duration) {
        for (int64_t k = t; k < end; ++k) result.contact[static_cast<size_t>(k * result.feet + f)] = 0;
      } else {
        result.phases.push_back({f, t, end});
      }
      t = end;
    }
  }
  return result;
}

}  // namespace syn
