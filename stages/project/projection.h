// syn-project: a retargeted motion (typically text-to-motion output) filtered
// through a style's synergy subspace while keeping a library-composed torso
// (paper, "Projection of text-to-motion output"):
//
//   û = S Sᵀ N_t u_in + û_t
//
// S: the style's shared basis (orthonormal columns; base velocities in the
// pelvis heading frame, so it is turned by each frame's heading), N_t: the
// torso-orientation null space (torso_null_space.h), û_t: the torso motion —
// by default J̄_t J_t S Sᵀ u_in, the torso part of the library's own
// reconstruction of the input; or J̄_t J_t of a composed motion. N_t is
// evaluated on the input's configuration at each frame; q̂ integrates û from
// the input's first pose.
#pragma once

#include <optional>
#include <string>

#include <Eigen/Core>

#include "common/model.h"
#include "common/motion_file.h"

namespace syn {

struct ProjectionResult {
  MotionData motion;
  // Per-frame checks of the construction, the worst over all frames (relative to ‖u‖ or 1):
  double worst_task_leak = 0;        // ‖J_t N_t u_in‖ / ‖J_t‖‖u_in‖
  double worst_subspace_residual = 0;  // ‖(I − P)(û − û_t)‖ / ‖û − û_t‖, P = S Sᵀ turned by the heading
};

// `basis`: [k, nu] orthonormal rows (a library style's components). `torso_motion`: a motion on the same
// model whose velocities give û_t (sampled at the input's times, held past its ends), or nullptr for the
// default.
[[nodiscard]] ProjectionResult ProjectMotion(const MotionData& input, const Model& model, int torso_link,
                                             const Eigen::MatrixXd& basis, const MotionData* torso_motion);

}  // namespace syn
