#include "stages/retarget/branch_joints.h"

#include <algorithm>

namespace syn {

std::vector<bool> BranchCoordinates(const Model& model) {
  std::vector<bool> branch(static_cast<size_t>(model.nq()), false);
  for (const ModelJoint& joint : model.joints()) {
    if (joint.type != "revolute" || joint.q_index < 0) continue;
    const double lower = model.qLower()[joint.q_index], upper = model.qUpper()[joint.q_index];
    branch[static_cast<size_t>(joint.q_index)] = lower >= -0.3 && lower <= 0.0 && upper > 2.0;
  }
  return branch;
}

Eigen::VectorXd RetargetLowerLimits(const Model& model) {
  Eigen::VectorXd lower = model.qLower();
  const std::vector<bool> branch = BranchCoordinates(model);
  for (int i = 0; i < model.nq(); ++i) {
    if (branch[static_cast<size_t>(i)]) lower[i] = 0.0;
  }
  return lower;
}

void BendBranchJoints(const std::vector<bool>& branch, Eigen::VectorXd& q) {
  for (Eigen::Index i = 0; i < q.size(); ++i) {
    if (branch[static_cast<size_t>(i)]) q[i] = std::max(q[i], kBranchStart);
  }
}

}  // namespace syn
