// Branch joints: knees (and any joint like them) whose range reaches at most a little backwards but far
// forwards. Their leg or arm can only be straightened to the backward limit through the mirrored branch,
// and a straight limb's targets cannot tell +θ from −θ, so a solver that lets them cross zero ends with the
// joint locked on its backward limit while the real one bends forward again (G1's knee allows −5°: the
// same-robot round trip found G1 knees on −5° against +16..80° in its source). The per-frame IK, the
// trajectory refinement and contact enforcement's leg solves keep them at or above zero; the take's first
// frame starts from kBranchStart, an IK frame that ends on zero is solved again from there (FrameIk::solve),
// and an enforced leg that starts below zero starts from it.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "common/model.h"

namespace syn {

inline constexpr double kBranchStart = 0.2;  // rad

// [nq]: whether each coordinate is a branch joint's: revolute, lower limit in [−0.3, 0] rad, upper above
// 2 rad (G1's and H1's knees; HRP-4C's arm joints j20/j26, −0.3 .. 1.4 rad, are not: treating them as
// knees turned its virtual base through 2π in a frame on a C3D capture).
[[nodiscard]] std::vector<bool> BranchCoordinates(const Model& model);

// [nq]: the model's lower limits, with each branch joint's raised to 0.
[[nodiscard]] Eigen::VectorXd RetargetLowerLimits(const Model& model);

// Bends every branch joint of q (`branch`: BranchCoordinates) to at least kBranchStart, where a solver can
// tell which way it bends.
void BendBranchJoints(const std::vector<bool>& branch, Eigen::VectorXd& q);

}  // namespace syn
