// TreeKinematics (the URDF joint frames multiplied out) against the Simbody Workspace: every link's pose
// and origin Jacobian at random configurations of every humanoid the project has, free, fixed and
// virtual-chain bases alike.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <string>
#include <vector>

#include "common/model.h"
#include "common/random.h"
#include "common/tree_kinematics.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

void ExpectSameAsWorkspace(const std::string& urdf) {
  SCOPED_TRACE(urdf);
  const Model model = Model::Load(urdf);
  Workspace workspace(model);
  TreeKinematics tree(model);
  SplitMix64 random(17);
  Eigen::Matrix<double, 6, Eigen::Dynamic> expected(6, model.nu()), got(6, model.nu());
  for (int sample = 0; sample < 20; ++sample) {
    Eigen::VectorXd q = model.defaultQ();
    for (int i = 0; i < model.nq(); ++i) {
      const double low = std::isfinite(model.qLower()[i]) ? model.qLower()[i] : -2.0;
      const double high = std::isfinite(model.qUpper()[i]) ? model.qUpper()[i] : 2.0;
      q[i] = random.uniform(low, high);
    }
    if (model.hasFreeBase()) {
      // A quaternion a little off the unit sphere: both normalise it.
      q.head<4>() = Eigen::Vector4d(random.normal(), random.normal(), random.normal(), random.normal()) * 1.3;
    }
    workspace.setQ(q);
    tree.setQ(q);
    for (int link = 0; link < static_cast<int>(model.linkNames().size()); ++link) {
      SCOPED_TRACE(model.linkNames()[static_cast<size_t>(link)]);
      const Eigen::Isometry3d want = workspace.findLinkPose(link), have = tree.linkPose(link);
      EXPECT_LT((want.translation() - have.translation()).norm(), 1e-12);
      EXPECT_LT((want.linear() - have.linear()).norm(), 1e-12);
      workspace.calcFrameJacobianWithSimbody(link, Eigen::Vector3d::Zero(), expected);
      tree.frameJacobian(link, got);
      EXPECT_LT((expected - got).cwiseAbs().maxCoeff(), 1e-12);
    }
  }
}

TEST(TreeKinematics, MatchesTheWorkspaceOnG1) { ExpectSameAsWorkspace(testing::SourcePath("datasets/robots/unitree_g1/g1_29dof.urdf")); }

TEST(TreeKinematics, MatchesTheWorkspaceOnEverySharedHumanoid) {
  SYN_REQUIRE_SHARED("robots/humanoid_synergies/HRP4c_optitrack_model.urdf");
  for (const char* urdf : {"robots/humanoid_synergies/HRP4c_optitrack_model.urdf", "robots/humanoid_synergies/HRP4c_model_dir.urdf",
                           "robots/humanoid_synergies/human_optitrack_model.urdf", "robots/humanoid_synergies/toro_optitrack_model.urdf",
                           "robots/unitree/h1.urdf", "robots/other/simple_humanoid.urdf"}) {
    ExpectSameAsWorkspace(testing::SharedPath(urdf));
  }
}

}  // namespace
}  // namespace syn
