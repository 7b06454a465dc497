// Targets the robot's legs can reach: the upper body lowered where a foot's target is further from its
// hip than the leg is long.
//
// A human scaled to a robot keeps the human's pelvis height over a stride the robot's shorter legs
// cannot span: at the end of a stance the planted foot is behind a pelvis that is too high, and the IK
// (all priority-1 tasks weighing alike) pulls the foot off its plant or the knee straight onto its
// limit. Humans lower the pelvis instead. So, frame by frame, the pelvis target (and with it every
// non-foot target, so the arms keep their reach) is lowered just enough that each foot target is
// within `margin` × leg length of its hip; the drop is then smoothed over time (a moving maximum, then a
// moving mean, over ±`smoothing` s) so it never jerks. What a lowered pelvis cannot fix (a foot
// target horizontally further than the leg) is counted, not forced onto the feet.
#pragma once

#include <cstdint>
#include <vector>

#include <Eigen/Core>

#include "common/model.h"
#include "stages/retarget/contact_detection.h"
#include "stages/retarget/frame_ik.h"

namespace syn {

struct LegReachOptions {
  // Fraction of the straight leg a foot target may be from its hip. 0.97: a knee bent ~20°, away from
  // the straight-knee singularity where the IK cannot tell which way the knee bends.
  double margin = 0.97;
  double smoothing = 0.1;  // s, half-window of the drop's smoothing
  // The drop never exceeds this fraction of the leg (0.15: ~10 cm on the G1, a walking human's pelvis
  // dips ~5 % of the leg): a stride far beyond the robot's legs (a scale that does not fit them) is
  // counted as out of reach, not answered by a crouch.
  double largest_drop = 0.08;
};

// One leg: the task tracking its foot, its hip in the pelvis link's frame, its straight length (m).
struct Leg {
  int foot = -1;  // index of the robot map's foot (the contacts' column)
  int foot_task = -1;
  Eigen::Vector3d hip_in_pelvis = Eigen::Vector3d::Zero();
  double length = 0.0;
};

// The legs from the model at the reference stance (workspace set to it): each foot task's link walked
// up to the pelvis task's link; the hip is the first joint below the pelvis. Empty when the chain does
// not pass through the pelvis link.
[[nodiscard]] std::vector<Leg> FindLegs(const Model& model, Workspace& workspace, int pelvis_link,
                                        const std::vector<int>& foot_tasks, const std::vector<IkTask>& tasks);

struct LegReachReport {
  int64_t lowered_frames = 0;      // frames whose upper body was lowered
  double largest_drop = 0.08;       // m
  int64_t unreachable_frames = 0;  // frames where a foot target is horizontally out of the leg's reach
};

// Lowers every non-foot target (frame_targets[t][i], i not a foot task) by the smoothed drop. Only planted
// feet (contacts) ask for a drop: a swing foot that misses its target a little harms nothing, a stance
// foot dragged off its plant is what a user sees.
LegReachReport LowerUpperBodyWithinReach(const std::vector<Leg>& legs, int pelvis_task, const FootContacts& contacts,
                                         const std::vector<double>& time_s, const LegReachOptions& options,
                                         std::vector<std::vector<IkTarget>>& frame_targets);

}  // namespace syn
