// How fast the retargeted motion lets a joint move. Each frame's step is bounded by the URDF velocity limit
// times the robot map's velocity_limit_scale (--velocity-limit-scale) times the frame's duration; the IK,
// the trajectory refinement and the contact enforcement's leg solves take that bound as a "scaled step
// time" s × dt and a per-joint speed, which this returns.
#pragma once

#include <algorithm>

namespace syn {

// rad/s: the fastest a scale above 1 lifts a joint to, G1's knee limit and about a sprinting person's knee.
// A scale above 1 stands for a person's pace where a robot's URDF limits fall short of it (HRP-4C's knees,
// 3.07 rad/s), not for the placeholder limits some URDFs give: HRP-4C's second ankle joints (50 rad/s)
// lifted 4 times let CMU 94_07 flip one from limit to limit in a frame.
inline constexpr double kFastestLiftedSpeed = 20.0;

// The joint's speed per unit of scaled step time (scale × dt), so that the step is at most
// min(scale × urdf_limit, max(urdf_limit, kFastestLiftedSpeed)) × dt: the URDF limit itself where scale <= 1.
inline double SpeedPerScaledSecond(double urdf_limit, double scale) {
  return scale > 1 ? std::min(urdf_limit, std::max(urdf_limit, kFastestLiftedSpeed) / scale) : urdf_limit;
}

}  // namespace syn
