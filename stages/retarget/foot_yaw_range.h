// How far a robot can turn each foot about the vertical relative to its pelvis, and foot targets held
// within it.
//
// A capture's foot orientation can turn further about the vertical than any leg: CMU 94_07's right foot
// swivels 200° in 50 ms (a BVH twist flipping) and stays turned for most of the take. The IK weighs a radian
// of orientation error like a metre of position error, so it bent the whole leg onto its limits (G1's hip
// pitch -145°, roll and yaw on their ranges, knee straight) to turn the foot a little further, and left the
// foot 0.47 m and the pelvis 0.23-0.4 m off their targets for 1,380 frames, the robot's pelvis at times on
// the floor while the dancer stood. A turn no leg makes cannot be tracked; the rest of the target can.
#pragma once

#include <vector>

#include <Eigen/Geometry>

#include "common/model.h"

namespace syn {

// rad: the foot's turn about the pelvis's vertical axis, relative to the reference stance, that its leg's
// joints can make: the sum of the position ranges of the joints between the pelvis and the foot whose axes
// are within kVerticalJointTolerance of vertical in the reference stance (G1: hip yaw, ±1.2 rad under its
// map's [joint_ranges]; HRP-4C: hip yaw ±0.8 and ankle yaw ±0.5).
struct YawRange {
  double lower = -M_PI;
  double upper = M_PI;
};

// The range of `foot_link` relative to `pelvis_link` at q_reference (sets the workspace to it). A foot
// not below the pelvis link in the tree, or a chain with no vertical joint, gets ±π (no limit).
[[nodiscard]] YawRange FootYawRange(const Model& model, Workspace& workspace, const Eigen::VectorXd& q_reference,
                                    int pelvis_link, int foot_link);

// `foot` (a foot target's orientation) with its turn about the pelvis target's vertical axis relative to
// the reference stance (`reference`: the foot link's orientation relative to the pelvis link's there) held
// within `range`; its tilt (the swing left after that turn) is kept. Returns whether it was held.
bool HoldFootYaw(const Eigen::Quaterniond& pelvis, const Eigen::Quaterniond& reference, const YawRange& range,
                 Eigen::Quaterniond& foot);

}  // namespace syn
