// Trajectory refinement (DESIGN.md, Retarget): the per-frame IK solutions,
// adjusted together so that the trajectory is smooth and still tracks the
// landmark targets. Over overlapping windows, one sparse least-squares
// problem (Ceres, sparse normal Cholesky from SuiteSparse) in the
// velocity-space corrections x_t (q_t = q_t^IK ⊕ x_t, quaternion-aware):
//
//   Σ_t ‖r_t + J_t x_t‖²                        each frame's IK residual, linearised at its solution
//   + Σ_t ‖s · σ_t · a_t · (0.01 s)²‖²           a_t: the acceleration (second difference of q over time)
//                                                σ_t: the IK's factor on its own smoothing at frame t
//                                                (FrameIk::regularisationScale: below 1 where the targets
//                                                are met exactly, so they stay met)
//
// with joints the IK left on a limit held there. Afterwards every frame is
// clamped to the joint limits and, frame by frame, to the URDF velocity limit
// from the previous frame (the bound the per-frame IK keeps). s = --smoothing: with s = 1, an
// acceleration of 10 rad/s² costs as much as 1 mm of tracking error at
// weight 1. Windows of 60 frames overlap by 15; the first two frames of each
// window keep the previous window's answer, so the joins are smooth too.
#pragma once

#include <vector>

#include "common/model.h"
#include "stages/retarget/frame_ik.h"

namespace syn {

struct RefinementOptions {
  double smoothing = 1.0;  // 0: off
  int window = 60;
  int overlap = 15;
  // Each joint's per-frame change is at most this fraction of its URDF velocity limit × dt (0: unbounded).
  double velocity_limit_scale = 1.0;
};

// `targets[t]` empty: no target that frame (smoothness alone decides it). q: [T, nq] row-major, in place.
void RefineTrajectory(FrameIk& ik, const Model& model, const std::vector<std::vector<IkTarget>>& targets,
                      const std::vector<double>& times, std::vector<double>& q, const RefinementOptions& options);

}  // namespace syn
