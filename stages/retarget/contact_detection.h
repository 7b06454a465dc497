// Foot contacts of the source capture: per foot and frame, whether the
// subject's foot is planted, from its landmark trajectory alone.
//
// A foot is planted while its landmark is low — within `height` of the
// capture's ground, estimated from the data as a low percentile of both feet's
// landmark heights (the level a planted foot's landmark sits at; captures put
// their floor anywhere) — and slow — horizontal speed, over a centred window,
// under `speed`. Hysteresis: a contact begins below (height, speed) and ends
// only above (height, speed) × `release`, so noise at the threshold does not
// toggle it; phases shorter than `min_duration` are dropped, but for a phase the
// recording's first or last frame cuts (it lasted longer than what was captured).
//
// Uneven ground (`uneven_ground`, on by default): a capture over blocks, steps or ramps (CMU subject 03's
// "walk on uneven terrain": stances 3-16 cm above its floor) has most stances too high for the ground's
// band; with it alone 03_01 had one contact phase in 3.6 s of walking and the robot's feet were free to
// slide through every step. A walk has no flight phase, so a slow foot (under `speed`) whose other foot
// swings above it (faster than speed × release, and higher) carries the body, whatever it stands on.
// Such a contact's level is the landmark's height where it began, and it ends, as one on the floor does,
// above level + height × release or faster than speed × release. The other foot must step meanwhile
// (travel `min_step`, a short human step, from the phase's first frame to its last), or the phase keeps
// only its frames within the floor's band: a foot turning on its ball swings fast without going anywhere
// (CMU 94_07's squat on its toes, ankles 5-7 cm up, drifted 101 mm planted flat). "Higher": a dancer
// kneeling on one leg (94_07 at 2.2-3 s, the knelt foot's ankle under the other's) stands on the knee, not
// on the raised foot (planted, it drifted 136 mm). A foot held still in the air (a dancer on one leg) is
// not taken for one either: its other foot, the standing one, is below it and slow. On the 17 flat CMU
// walks the contacts are unchanged but for 2 frames of 09_12.
//
// Defaults (metres and seconds of the capture, before scaling to the robot):
// 5 cm is the GMD foot-skating contact height (Karunratanakul et al. 2023,
// common/foot_sliding.h), and a contact ends at 0.5 m/s, GMD's sliding
// speed: a foot faster than that is sliding by definition, so it cannot be
// planted. It begins at 0.5/1.5 = 0.33 m/s. 0.1 s is the shortest human
// stance (sprinting ground contact lasts ~0.1 s).
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace syn {

struct ContactDetectionOptions {
  double height = 0.05;          // m above the estimated ground, to begin a contact
  double speed = 0.5 / 1.5;      // m/s horizontal, to begin a contact
  double release = 1.5;          // a contact ends above height × release or speed × release
  double min_duration = 0.1;     // s; shorter phases are dropped
  double ground_percentile = 0.02;  // of both feet's landmark heights: the planted level
  double speed_window = 0.05;    // s, centred window of the speed estimate
  bool uneven_ground = true;     // also plant a slow foot above the ground band while the other swings above it
  double min_step = 0.2;         // m the other foot travels during such a raised contact, or it is dropped

  bool IsValid(std::string* error) const;
};

// One contact phase of one foot: frames [begin, end) .
struct ContactPhase {
  int foot = 0;
  int64_t begin = 0, end = 0;
};

struct FootContacts {
  int64_t frames = 0;
  int feet = 0;
  std::vector<uint8_t> contact;  // [T, feet]: 1 = planted
  double ground = 0.0;           // m: the capture's estimated planted level
  std::vector<ContactPhase> phases;  // sorted by foot, then begin

  bool at(int64_t frame, int foot) const { return contact[static_cast<size_t>(frame * feet + foot)] != 0; }
  // The same for a robot foot index, which may lie past the detected feet (a foot with no landmark): unplanted.
  bool planted(int64_t frame, size_t foot) const { return foot < static_cast<size_t>(feet) && at(frame, static_cast<int>(foot)); }
  int64_t framesInContact(int foot) const;
};

// foot_positions[f]: foot f's landmark positions per frame (NaN = missing: not in contact), z up.
[[nodiscard]] FootContacts DetectContacts(const std::vector<std::vector<Eigen::Vector3d>>& foot_positions,
                                          const std::vector<double>& time_s, const ContactDetectionOptions& options);

}  // namespace syn
