// Principal axes of centred samples: a thin SVD, each axis signed so that its largest entry is positive.
//
// syn-synergies (one segment's synergies) and syn-library (a style's basis over many trials) both decompose
// velocity samples this way, and their outputs must read the same way round: an SVD may return either sign
// of a singular vector, so the sign is fixed here, once. The SVD lives in one translation unit: Eigen's
// BDCSVD is the most expensive template this code base instantiates (about a minute and a half per file
// under GCC's sanitizers).
#pragma once

#include <Eigen/Core>

namespace syn {

struct PrincipalAxes {
  Eigen::MatrixXd axes;             // columns: the first k right singular vectors, largest entry positive
  Eigen::VectorXd singular_values;  // all min(rows, cols) of them, largest first
  Eigen::MatrixXd scores;           // rows × k: the left singular vectors, signed as `axes` (if asked for)
  Eigen::VectorXd explained_variance_ratio;  // k: each axis's σ² over the sum of all σ² (zeros if that is 0)
};

// k = min(components, min(rows, cols)). `centred` must be non-empty; its column means are not removed here.
[[nodiscard]] PrincipalAxes ComputePrincipalAxes(const Eigen::MatrixXd& centred, int components, bool with_scores);

}  // namespace syn
