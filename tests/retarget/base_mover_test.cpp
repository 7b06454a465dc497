#include "stages/retarget/base_mover.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <string>
#include <vector>

#include "common/model.h"
#include "tests/support/demo_motion.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

// Moving the base by (ω, v) must leave the base link at R' = exp(ω) R, p' = p + v, read back by the model's
// own forward kinematics, and leave every other coordinate alone — for a free base and for a virtual chain.
void ExpectMovesTheBaseLink(const Model& model, const Eigen::VectorXd& start) {
  const BaseMover mover(model);
  ASSERT_TRUE(mover.canMove());
  Workspace workspace(model);
  workspace.setQ(start);
  const Eigen::Isometry3d before = workspace.findLinkPose(mover.link());
  Eigen::Matrix<double, 6, 1> correction;
  correction << 0.3, -0.2, 0.5, 0.12, -0.07, 0.05;
  Eigen::VectorXd q = start;
  mover.apply(correction, q);
  workspace.setQ(q);
  const Eigen::Isometry3d after = workspace.findLinkPose(mover.link());
  const Eigen::Matrix3d expected = Eigen::AngleAxisd(correction.head<3>().norm(), correction.head<3>().normalized()) * before.linear();
  EXPECT_LT((after.linear() - expected).norm(), 1e-9);
  EXPECT_LT((after.translation() - before.translation() - correction.tail<3>()).norm(), 1e-9);
  int changed = 0;
  for (Eigen::Index i = 0; i < q.size(); ++i) changed += std::abs(q[i] - start[i]) > 0;
  EXPECT_LE(changed, 7);  // the base's own coordinates only
}

TEST(BaseMover, MovesAFreeBase) {
  const Model model = Model::Load(testing::SourcePath(testing::kG1Urdf));
  Eigen::VectorXd q = model.defaultQ();
  q.segment<3>(4) << 0.2, -0.1, 0.75;
  q.head<4>() << std::cos(0.2), 0.0, std::sin(0.2) * 0.6, std::sin(0.2) * 0.8;  // a turned pelvis
  ExpectMovesTheBaseLink(model, q);
}

TEST(BaseMover, MovesHrp4csVirtualBaseChain) {
  SYN_REQUIRE_SHARED("robots/humanoid_synergies/HRP4c_optitrack_model.urdf");
  const Model model = Model::Load(testing::SharedPath("robots/humanoid_synergies/HRP4c_optitrack_model.urdf"));
  ASSERT_FALSE(model.hasFreeBase());
  Eigen::VectorXd q = model.defaultQ();
  // The chain's slides and turns, then a knee: rotations near the x-y-z angles' wrap, so the answer must be
  // the one nearest the start.
  const std::vector<std::string>& names = model.coordinateNames();
  const auto set = [&](const std::string& name, double value) {
    q[std::find(names.begin(), names.end(), name) - names.begin()] = value;
  };
  set("floating_base_p1", 0.3), set("floating_base_p2", -0.2), set("floating_base_p3", 0.8);
  set("floating_base_r1", 0.1), set("floating_base_r2", -0.3), set("floating_base_r3", 3.0);
  ExpectMovesTheBaseLink(model, q);
  const BaseMover mover(model);
  Eigen::VectorXd moved = q;
  Eigen::Matrix<double, 6, 1> turn;
  turn << 0, 0, 0.4, 0, 0, 0;  // past π on the yaw angle: continued, not wrapped to -π
  mover.apply(turn, moved);
  const double yaw = moved[std::find(names.begin(), names.end(), "floating_base_r3") - names.begin()];
  EXPECT_GT(yaw, M_PI);
  EXPECT_LT(std::abs(yaw - 3.0), 1.0);
}

}  // namespace
}  // namespace syn
