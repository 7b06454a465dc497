// Foot targets that agree with the source's contacts, before the IK sees them.
//
// The contact constraints (frame_ik.h) hold a planted foot flat at its touchdown pose and every sole point
// above the floor. Left alone, the foot's target disagrees with them: a scaled human foot lands heel first
// and tilted, often below the robot's floor, and keeps creeping while planted. The constraint then wins
// in one frame (the foot snaps flat at touchdown, the base jerks) and lets go in one frame at lift-off.
// So the targets are made consistent first, as animators plant feet:
// - during a contact phase the foot's target is its touchdown pose flattened onto z = 0 (FlatOnFloor:
//   the yaw and the sole centre's x, y where the source foot touched down);
// - over `approach` seconds before a touchdown the target blends (smoothstep) from the source's pose to
//   that planted pose, and over the same time after a lift-off back from it, each window at most half
//   the swing, so the foot arrives flat and leaves smoothly;
// - a free foot's target whose sole would be below the floor is raised onto it.
// The source's own targets stay what the landmark errors are measured against.
#pragma once

#include <vector>

#include "stages/retarget/contact_detection.h"
#include "stages/retarget/frame_ik.h"

namespace syn {

struct FootTargetOptions {
  // Blend time before a touchdown and after a lift-off (s). 0.1 s: a quarter of a walking swing
  // (~0.4 s), long enough that a 10° heel-strike tilt turns flat at ~2 rad/s instead of in one frame.
  double approach = 0.1;
  // A planted foot pitches with the source about its toe or heel edge beyond this (rad): 0.05 ≈ 3°,
  // above a flat foot's marker noise, so a flat stance stays exactly flat.
  double roll_dead_zone = 0.05;
};

// frame_targets[t][i]: every frame's targets (inactive where the landmark is missing); foot_task[f]: the
// task that tracks foot f's link (-1: none, the foot is left as it is). Changes the foot tasks' targets.
void ShapeFootTargets(const std::vector<IkFoot>& feet, const std::vector<int>& foot_task, const FootContacts& contacts,
                      const std::vector<double>& time_s, const FootTargetOptions& options,
                      std::vector<std::vector<IkTarget>>& frame_targets);

}  // namespace syn
