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
  std::vector<std::vector<double>> speeds(static_cast<size_t>(result.feet));
  for (int f = 0; f < result.feet; ++f) {
    speeds[static_cast<size_t>(f)] = CentredHorizontalSpeeds(foot_positions[static_cast<size_t>(f)], time_s, options.speed_window);
  }
  for (int f = 0; f < result.feet; ++f) {
    const std::vector<Eigen::Vector3d>& p = foot_positions[static_cast<size_t>(f)];
    const std::vector<double>& speed_of = speeds[static_cast<size_t>(f)];
    bool planted = false;
    double level = result.ground;  // the height the present contact stands at
    std::vector<uint8_t> raised(static_cast<size_t>(frames), 0);  // planted above the ground's band
    for (int64_t t = 0; t < frames; ++t) {
      const size_t k = static_cast<size_t>(t);
      const Eigen::Vector3d& here = p[k];
      const double speed = speed_of[k];
      if (std::isnan(speed)) {  // the foot or a window end missing
        planted = false;
        continue;
      }
      if (planted) {
        planted = here.z() - level <= options.height * options.release && speed <= options.speed * options.release;
      } else if (speed <= options.speed) {
        if (here.z() - result.ground <= options.height) {
          planted = true, level = result.ground;
        } else if (options.uneven_ground && result.feet == 2) {
          // The other foot swinging above this one: this one carries the body, on whatever it stands on.
          const size_t other = static_cast<size_t>(1 - f);
          if (speeds[other][k] > options.speed * options.release && foot_positions[other][k].z() > here.z()) {
            planted = true, level = here.z();
          }
        }
      }
      result.contact[static_cast<size_t>(t * result.feet + f)] = planted;
      raised[k] = planted && level != result.ground;
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
      // A raised contact is a step only if the other foot stepped meanwhile: a foot turning on its ball
      // swings fast without going anywhere. Without a step, the phase keeps only what is on the floor's
      // band (it may have begun raised and come down).
      if (raised[static_cast<size_t>(t)]) {
        const std::vector<Eigen::Vector3d>& other = foot_positions[static_cast<size_t>(1 - f)];
        const Eigen::Vector3d travel = other[static_cast<size_t>(end - 1)] - other[static_cast<size_t>(t)];
        if (!(travel.allFinite() && travel.head<2>().norm() >= options.min_step)) {
          int64_t floor = t;
          while (floor < end && p[static_cast<size_t>(floor)].z() - result.ground > options.height) ++floor;
          for (int64_t k = t; k < floor; ++k) result.contact[static_cast<size_t>(k * result.feet + f)] = 0;
          if (floor > t) continue;  // the rest, if any, is looked at as a phase of its own
        }
      }
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
