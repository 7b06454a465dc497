#include "stages/retarget/contact_forces.h"

#include <Eigen/Cholesky>
#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>

namespace syn {

NonNegativeLeastSquares::NonNegativeLeastSquares(int rows, int max_columns)
    : rows_(rows),
      max_columns_(max_columns),
      a_(Eigen::MatrixXd::Zero(rows, max_columns)),
      ata_(max_columns, max_columns),
      reduced_(max_columns, max_columns),
      x_(Eigen::VectorXd::Zero(max_columns)),
      z_(max_columns),
      w_(max_columns),
      atb_(max_columns),
      reduced_rhs_(max_columns),
      reduced_solution_(max_columns),
      factor_(max_columns),
      passive_(static_cast<size_t>(max_columns), 0),
      index_(static_cast<size_t>(max_columns), 0) {}

// z = least squares over the passive columns only (0 elsewhere), from the normal equations.
void NonNegativeLeastSquares::solvePassive(int columns, const Eigen::VectorXd& /*b*/, Eigen::VectorXd& z) {
  int count = 0;
  for (int j = 0; j < columns; ++j) {
    if (passive_[static_cast<size_t>(j)]) index_[static_cast<size_t>(count++)] = j;
  }
  z.setZero();
  if (count == 0) return;
  // A fixed-size system padded with the identity keeps the factorisation allocation-free; a tiny ridge
  // keeps it definite when passive columns are dependent (more contact edges than wrench dimensions).
  reduced_.setIdentity();
  reduced_rhs_.setZero();
  for (int r = 0; r < count; ++r) {
    const int i = index_[static_cast<size_t>(r)];
    reduced_rhs_[r] = atb_[i];
    for (int c = 0; c < count; ++c) reduced_(r, c) = ata_(i, index_[static_cast<size_t>(c)]);
    reduced_(r, r) += 1e-9 * (1.0 + ata_(i, i));
  }
  factor_.compute(reduced_);
  reduced_solution_ = factor_.solve(reduced_rhs_);
  for (int r = 0; r < count; ++r) z[index_[static_cast<size_t>(r)]] = reduced_solution_[r];
}

void NonNegativeLeastSquares::solve(int columns, const Eigen::VectorXd& b) {
  const auto a = a_.leftCols(columns);
  ata_.topLeftCorner(columns, columns).noalias() = a.transpose() * a;
  atb_.head(columns).noalias() = a.transpose() * b;
  x_.setZero();
  std::fill(passive_.begin(), passive_.end(), 0);
  constexpr double kTolerance = 1e-10;
  for (int outer = 0; outer < 3 * max_columns_; ++outer) {
    // Gradient of −½‖Ax − b‖²: the most promising active column joins the passive set.
    w_.head(columns) = atb_.head(columns) - ata_.topLeftCorner(columns, columns) * x_.head(columns);
    int best = -1;
    double best_w = kTolerance * (1.0 + atb_.head(columns).cwiseAbs().maxCoeff());
    for (int j = 0; j < columns; ++j) {
      if (!passive_[static_cast<size_t>(j)] && w_[j] > best_w) best = j, best_w = w_[j];
    }
    if (best < 0) break;
    passive_[static_cast<size_t>(best)] = 1;
    for (int inner = 0; inner < 3 * max_columns_; ++inner) {
      solvePassive(columns, b, z_);
      double alpha = 1.0;
      bool feasible = true;
      for (int j = 0; j < columns; ++j) {
        if (passive_[static_cast<size_t>(j)] && z_[j] <= 0) {
          feasible = false;
          alpha = std::min(alpha, x_[j] / (x_[j] - z_[j]));
        }
      }
      if (feasible) {
        x_.head(columns) = z_.head(columns);
        break;
      }
      x_.head(columns) += alpha * (z_.head(columns) - x_.head(columns));
      for (int j = 0; j < columns; ++j) {
        if (passive_[static_cast<size_t>(j)] && x_[j] <= kTolerance) passive_[static_cast<size_t>(j)] = 0, x_[j] = 0;
      }
    }
  }
}

ContactForceSplit::ContactForceSplit(int max_points, const ContactForceOptions& options)
    : options_(options), nnls_(6, 4 * std::max(max_points, 1)), target_(6) {
  column_point_.reserve(static_cast<size_t>(4 * max_points));
  column_direction_.reserve(static_cast<size_t>(4 * max_points));
}

void ContactForceSplit::split(const std::vector<Eigen::Vector3d>& sole_points, const std::vector<int>& foot_of_point,
                              int feet, const Eigen::Vector3d& base_origin, const Eigen::Matrix<double, 6, 1>& residual,
                              std::vector<Eigen::Vector3d>& foot_force, Eigen::Matrix<double, 6, 1>& unexplained) {
  column_point_.clear();
  column_direction_.clear();
  const double mu = options_.friction;
  const Eigen::Vector3d edges[4] = {{mu, 0, 1}, {-mu, 0, 1}, {0, mu, 1}, {0, -mu, 1}};
  for (size_t p = 0; p < sole_points.size(); ++p) {
    if (sole_points[p].z() > options_.touch_height) continue;
    for (const Eigen::Vector3d& edge : edges) {
      const int column = static_cast<int>(column_point_.size());
      const Eigen::Vector3d direction = edge.normalized();
      nnls_.a().col(column).head<3>() = (sole_points[p] - base_origin).cross(direction);
      nnls_.a().col(column).tail<3>() = direction;
      column_point_.push_back(static_cast<int>(p));
      column_direction_.push_back(direction);
    }
  }
  foot_force.assign(static_cast<size_t>(feet), Eigen::Vector3d::Zero());
  target_ = residual;
  const int columns = static_cast<int>(column_point_.size());
  if (columns == 0) {
    unexplained = residual;
    return;
  }
  nnls_.solve(columns, target_);
  Eigen::Matrix<double, 6, 1> explained = Eigen::Matrix<double, 6, 1>::Zero();
  for (int c = 0; c < columns; ++c) {
    const double magnitude = nnls_.x()[c];
    if (magnitude <= 0) continue;
    explained += magnitude * nnls_.a().col(c);
    foot_force[static_cast<size_t>(foot_of_point[static_cast<size_t>(column_point_[static_cast<size_t>(c)])])] +=
        magnitude * column_direction_[static_cast<size_t>(c)];
  }
  unexplained = residual - explained;
}

}  // namespace syn
