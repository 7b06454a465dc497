#include "common/segment_synergies.h"

#include <algorithm>

namespace syn {

Eigen::MatrixXd ReconstructVelocities(const SegmentSynergies& synergies, const Eigen::VectorXd& coefficients) {
  const Eigen::Index k = std::min<Eigen::Index>(coefficients.size(), synergies.components.rows());
  Eigen::MatrixXd reconstruction = synergies.scores.leftCols(k) * coefficients.head(k).asDiagonal() *
                                   synergies.components.topRows(k);
  reconstruction.rowwise() += synergies.mean.transpose();
  return reconstruction;
}

}  // namespace syn
