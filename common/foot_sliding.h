// Foot sliding (DESIGN.md, Method: Metrics): a frame slides when a foot is on
// the ground — its lowest sole point within `contact_height` of z = 0 — and
// moves horizontally faster than `slide_speed`, or when a foot penetrates
// the ground by more than `penetration`.
//
// Defaults are the text-to-motion community's foot-skating measure (GMD,
// Karunratanakul et al. 2023, used by later MDM-family papers): contact below
// 5 cm, sliding above 2.5 cm per frame at HumanML3D's 20 fps = 0.5 m/s. The
// speed is the displacement of the sole centroid across a centred window
// (default 0.05 s, one HumanML3D frame), so a sensor-rate jitter does not
// count as sliding.
#pragma once

#include <cstdint>
#include <vector>

namespace syn {

struct FootSlidingOptions {
  double contact_height = 0.05;  // m
  double slide_speed = 0.5;      // m/s
  double window = 0.05;          // s, centred
  double penetration = 0.01;     // m below z = 0
};

// One foot at one evaluation frame: the centroid of its sole points and the lowest one's height.
struct FootSample {
  double x = 0, y = 0;
  double lowest_z = 0;
};

// feet[f][k]: foot f at frame k of a uniform grid with spacing `dt`. Returns one flag per frame.
[[nodiscard]] std::vector<uint8_t> FindSlidingFrames(const std::vector<std::vector<FootSample>>& feet, double dt,
                                                     const FootSlidingOptions& options);

}  // namespace syn
