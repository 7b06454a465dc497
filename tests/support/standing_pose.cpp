#include "tests/support/standing_pose.h"

#include <algorithm>

#include "common/model.h"

namespace syn::testing {

Eigen::VectorXd StandingZeroPose(const Model& model, const RobotMap& map) {
  Workspace workspace(model);
  Eigen::VectorXd q = model.defaultQ();
  workspace.setQ(q);
  double lowest = 1e9;
  for (const RobotFoot& foot : map.feet) {
    const Eigen::Isometry3d pose = workspace.findLinkPose(model.findLinkIndex(foot.link));
    for (const auto& p : foot.sole_points) lowest = std::min(lowest, (pose * Eigen::Vector3d(p[0], p[1], p[2])).z());
  }
  const auto& names = model.coordinateNames();
  const auto base_z = std::find(names.begin(), names.end(), "base_z");
  q[base_z - names.begin()] -= lowest;
  return q;
}

}  // namespace syn::testing
