// The capture's floor as a plane, and the take turned so that plane is level.
//
// Motion-capture floors are calibrated by hand and are often not level in the data: CMU's walks rise
// 13-21 mm per metre walked (subjects 02, 07, 08) or fall 5-8 mm/m (09, 10, 12), about 1°. Contact
// detection measures a foot's height above one ground height, so at the far end of a 2.5 m walk the planted
// feet stood 4-5 cm "above the ground" and were not detected (CMU 08_04: no foot planted for its last
// 1.8 s), and the robot, whose floor is level, walked up the slope with straightening legs and its soles
// 2-5 cm in the air.
//
// The plane: the stance samples of every foot landmark (horizontal speed under `still_speed` over a
// centred window) fitted by least squares z = a x + b y + c, then refitted without the samples more than
// `band` above it (a heel rising before the foot moves is slow and high), three times. Along a horizontal
// direction the stance samples spread less than `min_spread` (standard deviation; a dance in place) the
// slope is not observable and is taken as zero. The fit is used only if it is a floor: the tilt at most
// `max_tilt`, the kept samples within `max_residual` (standard deviation) of the plane and at least
// `min_kept` of all the stance samples; otherwise
// (CMU 03_0x walk over uneven terrain: 26-53 mm) the take keeps its axes and a note says why. A tilt under
// `min_tilt` is within what a level floor's fit gives, and is left alone too.
// Levelling turns every landmark's position and orientation about the horizontal axis through the kept
// samples' centroid by the rotation taking the plane's normal to +z: no turn about z (heading unchanged),
// the floor's height at the centroid unchanged.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "stages/retarget/landmarks.h"

namespace syn {

struct FloorLevellingOptions {
  bool enabled = true;
  double still_speed = 0.1;   // m/s horizontal: a foot landmark this slow is standing
  double speed_window = 0.05;  // s, centred window of that speed (contact detection's)
  double band = 0.015;        // m above the plane: kept in the refits
  double min_spread = 0.15;   // m (standard deviation along a direction) to fit the slope along it
  double max_tilt = 0.05;     // rad (2.9°): more is not a floor the capture was calibrated on
  // rad (0.3°): less is left alone. A level floor's fit is not exactly level: the Kimodo G1 dance, on a
  // level floor, fits 0.22° from its feet sliding and dipping 15-38 mm; and 0.3° raises a 2.5 m walk's far
  // end by 13 mm, a quarter of the contact height.
  double min_tilt = 0.005;
  double max_residual = 0.015;  // m (standard deviation of the kept samples)
  // The least share of the stance samples the plane keeps: fewer, and it is the lowest of several levels
  // (stepping stones), not the floor with some heels rising. CMU walks keep 0.87-1.0, dances 0.58-1.0
  // (kneeling and tiptoes are slow and high), the walks over uneven terrain 0.13-0.29 (and 03_01 0.67,
  // with 39 mm residual).
  double min_kept = 0.5;

  bool IsValid(std::string* error) const;
};

struct FloorPlane {
  bool levelled = false;          // the take was turned
  bool uneven = false;            // its stance samples fit no floor (terrain, steps): the note says why
  double tilt_rad = 0;            // the plane's angle to the horizontal (also when not levelled)
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d centroid = Eigen::Vector3d::Zero();  // of the kept samples, on the plane
  double residual = 0;            // m, standard deviation of the kept samples from the plane
  int64_t samples = 0;            // kept stance samples
  double kept_fraction = 0;       // of all stance samples
  Eigen::Quaterniond rotation = Eigen::Quaterniond::Identity();  // normal -> +z when levelled
  std::string note;               // why it was not levelled, if it was not
};

// foot_positions[f][t]: foot landmark f's position (NaN = missing).
[[nodiscard]] FloorPlane EstimateFloorPlane(const std::vector<std::vector<Eigen::Vector3d>>& foot_positions,
                                            const std::vector<double>& time_s, const FloorLevellingOptions& options);

// Turns every pose of `landmarks` by the plane's rotation about its centroid (nothing when not levelled).
void LevelLandmarks(const FloorPlane& plane, LandmarkTrajectories& landmarks);

}  // namespace syn
