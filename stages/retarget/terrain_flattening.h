// A walk over uneven terrain (blocks, steps, stepping stones) replayed on the robot's flat floor.
//
// The robot's planted soles are flat on z = 0 (contact_enforcement.h), but a capture over blocks stands
// on them 6-22 cm above its floor (CMU 03_0x, "walk on uneven terrain"). Left as captured, every landmark
// above a raised plant asks the robot to be that much taller than its legs reach: CMU 03_02 onto HRP-4C
// had its pelvis targets 0.5 m out of reach (P1 median 167 mm), the contact enforcement lowered the base
// for each raised plant, and where the next plant came in reach only by a 20 cm drop in 0.1 s, the planted
// foot slid 66 mm under the moving body.
//
// So, on a take whose floor estimate finds no floor (floor_levelling.h: its stance samples fit no plane),
// the take is lowered to the floor it would have walked on had the terrain been flat:
//   - each foot's ground level: during a contact phase raised above the floor band (its landmark's median
//     height over the phase more than the contact height above the capture's ground; contact_detection.h),
//     that height; during a phase within the band, 0; between phases, linear in time from one phase's
//     level to the next's (a swing from a block to the floor comes down across the swing); before the
//     first phase and after the last, 0 where the foot is within the band at the take's first (last)
//     frame, else the nearest phase's level;
//   - each foot landmark is lowered by its own foot's level, so every plant lands on the floor;
//   - every other landmark (pelvis, torso, head, hands, elbows) by the mean of the two feet's levels: the
//     body sits between the feet, each on its block.
// Orientations and horizontal positions are unchanged. A take with a floor (every flat walk and dance) is
// left alone: there a plant above the band is a foot on its toes, not on a block.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "stages/retarget/contact_detection.h"
#include "stages/retarget/landmarks.h"

namespace syn {

struct TerrainFlattening {
  int64_t raised_phases = 0;  // contact phases above the floor band, lowered onto the floor
  double highest = 0.0;       // m (capture): the highest of them
};

// `foot_landmarks`: per foot of `contacts` (its columns), the landmark index it was detected from (-1:
// none). `band`: the contact detection's height (m). Lowers `landmarks` in place as above.
TerrainFlattening FlattenTerrain(const FootContacts& contacts, const std::vector<int64_t>& foot_landmarks, double band,
                                 LandmarkTrajectories& landmarks);

// The note a retarget summary gives for it ("" when nothing was lowered).
std::string TerrainFlatteningNote(const TerrainFlattening& flattening);

}  // namespace syn
