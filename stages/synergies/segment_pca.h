// PCA of one motion segment's generalized-velocity samples: the synergies
// (common/segment_synergies.h gives the maths and the reconstruction).
//
// Signs are fixed so that each direction's largest entry is positive, which
// makes the output deterministic (an SVD may return either sign; common/principal_axes.h,
// the convention syn-library's style bases share).
#pragma once

#include <Eigen/Core>

#include "common/segment_synergies.h"

namespace syn {

// k is capped at min(Ts, nv). Throws std::invalid_argument for an empty X.
[[nodiscard]] SegmentSynergies ComputeSegmentSynergies(const Eigen::MatrixXd& velocities, int components);

}  // namespace syn
