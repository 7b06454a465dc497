#include "stages/simulate/tree_mass_factorization.h"

#include <map>
#include <string>

#include "common/error.h"

namespace syn {

TreeMassFactorization::TreeMassFactorization(const Model& model) : parent_(static_cast<size_t>(model.nu()), -1) {
  // The moving joint that carries each link (fixed joints pass their parent's through).
  std::map<std::string, const ModelJoint*> joint_of_child;
  for (const ModelJoint& joint : model.joints()) joint_of_child[joint.child] = &joint;
  const auto last_velocity_above = [&](std::string link) {
    for (auto found = joint_of_child.find(link); found != joint_of_child.end(); found = joint_of_child.find(link)) {
      const ModelJoint& joint = *found->second;
      if (joint.u_index >= 0) return joint.u_index + (joint.type == "free" ? 5 : 0);
      link = joint.parent;
    }
    return -1;
  };
  for (const ModelJoint& joint : model.joints()) {
    if (joint.u_index < 0) continue;
    const int count = joint.type == "free" ? 6 : 1;
    parent_[static_cast<size_t>(joint.u_index)] = last_velocity_above(joint.parent);
    for (int i = 1; i < count; ++i) parent_[static_cast<size_t>(joint.u_index + i)] = joint.u_index + i - 1;
  }
  // The factorisation needs every parent numbered before its child (Simbody numbers velocities from
  // the root outwards).
  for (size_t i = 0; i < parent_.size(); ++i) {
    if (parent_[i] >= static_cast<int>(i)) {
      throw std::logic_error("TreeMassFactorization: velocity " + std::to_string(i) + " has parent " +
                             std::to_string(parent_[i]) + ", not numbered before it");
    }
  }
  ancestor_begin_.push_back(0);
  for (size_t k = 0; k < parent_.size(); ++k) {
    for (int i = parent_[k]; i >= 0; i = parent_[static_cast<size_t>(i)]) ancestors_.push_back(i);
    ancestor_begin_.push_back(static_cast<int>(ancestors_.size()));
  }
}

void TreeMassFactorization::factor(Workspace& workspace) {
  workspace.calcMassMatrix(mass_);
  factor_ = mass_;
  const int n = static_cast<int>(factor_.rows());
  // RBDA Table 6.3 (LTDL), on the lower triangle: from the leaves in, fold each velocity's row into its
  // ancestors'. Only ancestor entries are touched, which is where A's fill-in can be.
  for (int k = n - 1; k >= 0; --k) {
    for (int i = parent_[static_cast<size_t>(k)]; i >= 0; i = parent_[static_cast<size_t>(i)]) {
      const double ratio = factor_(k, i) / factor_(k, k);
      for (int j = i; j >= 0; j = parent_[static_cast<size_t>(j)]) factor_(i, j) -= ratio * factor_(k, j);
      factor_(k, i) = ratio;
    }
  }
  inverse_sqrt_d_ = factor_.diagonal().cwiseSqrt().cwiseInverse();
}

void TreeMassFactorization::solveInPlace(Eigen::VectorXd& x) const {
  // Lᵀ D L w = x, as one row: RBDA Table 6.4's back substitution, D, and the forward one.
  solveRowsL(x.data(), 1);
  for (Eigen::Index k = 0; k < x.size(); ++k) x[k] /= factor_(k, k);
  solveRowsLTranspose(x.data(), 1);
}

void TreeMassFactorization::solveRowsL(double* x, Eigen::Index rows) const {
  const int n = static_cast<int>(factor_.rows());
  for (int k = n - 1; k >= 0; --k) {
    const double* column_k = x + k * rows;
    for (int a = ancestor_begin_[static_cast<size_t>(k)]; a < ancestor_begin_[static_cast<size_t>(k) + 1]; ++a) {
      const int i = ancestors_[static_cast<size_t>(a)];
      const double l = factor_(k, i);
      double* column_i = x + i * rows;
      for (Eigen::Index r = 0; r < rows; ++r) column_i[r] -= l * column_k[r];
    }
  }
}

void TreeMassFactorization::solveRowsLTranspose(double* x, Eigen::Index rows) const {
  const int n = static_cast<int>(factor_.rows());
  for (int k = 0; k < n; ++k) {
    double* column_k = x + k * rows;
    for (int a = ancestor_begin_[static_cast<size_t>(k)]; a < ancestor_begin_[static_cast<size_t>(k) + 1]; ++a) {
      const int i = ancestors_[static_cast<size_t>(a)];
      const double l = factor_(k, i);
      const double* column_i = x + i * rows;
      for (Eigen::Index r = 0; r < rows; ++r) column_k[r] -= l * column_i[r];
    }
  }
}

void TreeMassFactorization::solveRowsInPlace(Eigen::MatrixXd& x) const {
  solveRowsL(x.data(), x.rows());
  for (Eigen::Index k = 0; k < x.cols(); ++k) x.col(k) /= factor_(k, k);
  solveRowsLTranspose(x.data(), x.rows());
}

void TreeMassFactorization::solveRowsInPlace(Eigen::MatrixXd& x, Eigen::MatrixXd& gram) const {
  solveRowsL(x.data(), x.rows());
  for (Eigen::Index k = 0; k < x.cols(); ++k) x.col(k) *= inverse_sqrt_d_[k];  // W
  gram.setZero(x.rows(), x.rows());
  gram.selfadjointView<Eigen::Lower>().rankUpdate(x);
  gram.triangularView<Eigen::StrictlyUpper>() = gram.transpose();
  for (Eigen::Index k = 0; k < x.cols(); ++k) x.col(k) *= inverse_sqrt_d_[k];
  solveRowsLTranspose(x.data(), x.rows());
}

}  // namespace syn
