#include "tests/support/standing_pose.h"

#include <algorithm>
#include <cmath>

#include <gtest/gtest.h>

#include "common/model.h"
#include "tests/support/synthetic_motions.h"

namespace syn::testing {

Eigen::VectorXd StandingZeroPose(const Model& model, const RobotMap& map) {
  Workspace workspace(model);
  Eigen::VectorXd q = model.defaultQ();
  const double lowest = LowestSolePoint(model, map, workspace, q);
  // The base's height: the free base's base_z, or the coordinate of a virtual base chain (HRP-4C's
  // floating_base_p3) that lifts the soles one for one.
  for (int i = 0; i < model.nq(); ++i) {
    Eigen::VectorXd raised = q;
    raised(i) += 1e-3;
    if (std::abs(LowestSolePoint(model, map, workspace, raised) - lowest - 1e-3) < 1e-9) {
      q(i) -= lowest;
      return q;
    }
  }
  ADD_FAILURE() << model.name() << " has no coordinate that raises it vertically";
  return q;
}

}  // namespace syn::testing
