#include "stages/synergies/segment_pca.h"

#include <stdexcept>

#include <Eigen/SVD>

namespace syn {

SegmentSynergies ComputeSegmentSynergies(const Eigen::MatrixXd& velocities, int components) {
  if (velocities.rows() == 0 || velocities.cols() == 0) throw std::invalid_argument("no velocity samples");
  SegmentSynergies result;
  result.mean = velocities.colwise().mean().transpose();
  const Eigen::MatrixXd centred = velocities.rowwise() - result.mean.transpose();
  const Eigen::BDCSVD<Eigen::MatrixXd> svd(centred, Eigen::ComputeThinU | Eigen::ComputeThinV);
  const Eigen::VectorXd sigma = svd.singularValues();
  const int available = static_cast<int>(sigma.size());
  const int k = std::min(components, available);
  Eigen::MatrixXd u = svd.matrixU().leftCols(k);
  Eigen::MatrixXd v = svd.matrixV().leftCols(k);
  for (int i = 0; i < k; ++i) {
    Eigen::Index largest = 0;
    v.col(i).cwiseAbs().maxCoeff(&largest);
    if (v(largest, i) < 0) {
      v.col(i) = -v.col(i);
      u.col(i) = -u.col(i);
    }
  }
  const double total = sigma.squaredNorm();
  result.components = v.transpose();
  result.singular_values = sigma.head(k);
  result.explained_variance_ratio = total > 0 ? Eigen::VectorXd(sigma.head(k).array().square() / total)
                                              : Eigen::VectorXd::Zero(k);
  result.scores = u;
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
