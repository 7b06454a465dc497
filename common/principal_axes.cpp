#include "common/principal_axes.h"

#include <algorithm>

#include <Eigen/SVD>

namespace syn {

PrincipalAxes ComputePrincipalAxes(const Eigen::MatrixXd& centred, int components, bool with_scores) {
  // Left vectors only when asked: BDCSVD then skips their accumulation.
  const unsigned int options = with_scores ? (Eigen::ComputeThinU | Eigen::ComputeThinV) : Eigen::ComputeThinV;
  const Eigen::BDCSVD<Eigen::MatrixXd> svd(centred, options);
  PrincipalAxes result;
  result.singular_values = svd.singularValues();
  const int k = std::min(components, static_cast<int>(result.singular_values.size()));
  result.axes = svd.matrixV().leftCols(k);
  if (with_scores) result.scores = svd.matrixU().leftCols(k);
  const double total = result.singular_values.squaredNorm();
  result.explained_variance_ratio = total > 0
                                        ? Eigen::VectorXd(result.singular_values.head(k).array().square() / total)
                                        : Eigen::VectorXd::Zero(k);
  for (int c = 0; c < k; ++c) {
    Eigen::Index largest = 0;
    result.axes.col(c).cwiseAbs().maxCoeff(&largest);
    if (result.axes(largest, c) < 0) {
      result.axes.col(c) = -result.axes.col(c);
      if (with_scores) result.scores.col(c) = -result.scores.col(c);
    }
  }
  return result;
}

}  // namespace syn
