#include "stages/synergies/segment_pca.h"

#include <stdexcept>
#include <utility>

#include "common/principal_axes.h"

namespace syn {

SegmentSynergies ComputeSegmentSynergies(const Eigen::MatrixXd& velocities, int components) {
  if (velocities.rows() == 0 || velocities.cols() == 0) throw std::invalid_argument("no velocity samples");
  SegmentSynergies result;
  result.mean = velocities.colwise().mean().transpose();
  const Eigen::MatrixXd centred = velocities.rowwise() - result.mean.transpose();
  PrincipalAxes principal = ComputePrincipalAxes(centred, components, /*with_scores=*/true);
  const Eigen::VectorXd& sigma = principal.singular_values;
  const int available = static_cast<int>(sigma.size());
  const double total = sigma.squaredNorm();
  result.components = principal.axes.transpose();
  result.singular_values = sigma.head(principal.axes.cols());
  result.explained_variance_ratio = principal.explained_variance_ratio;
  result.scores = std::move(principal.scores);
  double cumulative = 0;
  result.components_for_90_percent = available;
  for (int i = 0; i < available; ++i) {
    cumulative += total > 0 ? sigma[i] * sigma[i] / total : 1.0;
    if (cumulative >= 0.9 - 1e-12) {
      result.components_for_90_percent = i + 1;
      break;
    }
  }
  return result;
}

}  // namespace syn
