// Branch joints: knees (and any joint like them) whose range reaches at most a little backwards but far
// forwards. Their leg or arm can only be straightened to the backward limit through the mirrored branch,
// and a straight limb's targets cannot tell +θ from −θ, so a solver that lets them cross zero ends with the
// joint locked on its backward limit while the real one bends forward again (G1's knee allows −5°: the
// same-robot round trip found G1 knees on −5° against +16..80° in its source). The retargeter keeps them
// at or above zero, and a solve that ends on that floor is tried again from kBranchStart.
#pragma once

namespace syn {

inline constexpr double kBranchStart = 0.2;  // rad

// A revolute joint whose lower limit lies in [−0.3, 0] rad and whose upper one is above 1 rad.
inline bool IsBranchJoint(bool revolute, double lower, double upper) {
  return revolute && lower >= -0.3 && lower <= 0.0 && upper > 1.0;
}

}  // namespace syn
