// Eigen matrices are column-major; intermediate files are row-major [rows, cols].
#pragma once

#include <vector>

#include <Eigen/Core>

#include "common/intermediate_file.h"

namespace syn {

inline std::vector<double> RowMajorValues(const Eigen::MatrixXd& matrix) {
  std::vector<double> values(static_cast<size_t>(matrix.size()));
  Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(values.data(), matrix.rows(),
                                                                                      matrix.cols()) = matrix;
  return values;
}

inline Eigen::MatrixXd MatrixFromRowMajor(const DoubleArray& array) {
  const Eigen::Index rows = array.dims.empty() ? 0 : array.dims[0];
  const Eigen::Index cols = array.dims.size() > 1 ? array.dims[1] : 1;
  return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(array.values.data(),
                                                                                                  rows, cols);
}

}  // namespace syn
