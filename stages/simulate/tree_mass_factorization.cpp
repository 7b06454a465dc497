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
}

void TreeMassFactorization::solveInPlace(Eigen::VectorXd& x) const {
  const int n = static_cast<int>(factor_.rows());
  // Lᵀ y = x, D z = y, L w = z (RBDA Table 6.4's back and forward substitutions).
  for (int k = n - 1; k >= 0; --k) {
    for (int i = parent_[static_cast<size_t>(k)]; i >= 0; i = parent_[static_cast<size_t>(i)]) x[i] -= factor_(k, i) * x[k];
  }
  for (int k = 0; k < n; ++k) x[k] /= factor_(k, k);
  for (int k = 0; k < n; ++k) {
    for (int i = parent_[static_cast<size_t>(k)]; i >= 0; i = parent_[static_cast<size_t>(i)]) x[k] -= factor_(k, i) * x[i];
  }
}

void TreeMassFactorization::solveRowsInPlace(Eigen::MatrixXd& x) const {
  const int n = static_cast<int>(factor_.rows());
  for (int k = n - 1; k >= 0; --k) {
    for (int i = parent_[static_cast<size_t>(k)]; i >= 0; i = parent_[static_cast<size_t>(i)]) x.col(i) -= factor_(k, i) * x.col(k);
  }
  for (int k = 0; k < n; ++k) x.col(k) /= factor_(k, k);
  for (int k = 0; k < n; ++k) {
    for (int i = parent_[static_cast<size_t>(k)]; i >= 0; i = parent_[static_cast<size_t>(i)]) x.col(k) -= factor_(k, i) * x.col(i);
  }
}

}  // namespace syn
