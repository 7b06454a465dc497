// The ground's compliant contact (ground_contact.h) never pulls, not even within the linearly implicit
// step: a sole leaving the floor fast carries a positive force at the step's start whose tangent runs below
// zero over the step, and such points are taken out of the step's sums.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "common/error.h"
#include "common/model.h"
#include "common/robot_map.h"
#include "stages/simulate/ground_contact.h"
#include "tests/support/demo_motion.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

struct Sums {
  Eigen::VectorXd generalized;
  Eigen::MatrixXd stiffness, damping;
};

class GroundContactTest : public ::testing::Test {
 protected:
  const Model model = Model::Load(testing::SourcePath(testing::kG1Urdf));
  const RobotMap map = LoadRobotMap(testing::SourcePath("manifests/robots/g1.toml"));
  Workspace workspace{model};

  // G1 in its zero pose with its soles `depth` below the floor (all eight points: the pose's soles are
  // level) and the whole body moving up at `rising` m/s.
  void Place(double depth, double rising) {
    Eigen::VectorXd q = model.defaultQ(), u = Eigen::VectorXd::Zero(model.nu());
    workspace.setQ(q);
    double lowest = std::numeric_limits<double>::infinity();
    for (const RobotFoot& foot : map.feet) {
      const Eigen::Isometry3d pose = workspace.findLinkPose(model.findLinkIndex(foot.link));
      for (const std::array<double, 3>& p : foot.sole_points) lowest = std::min(lowest, (pose * Eigen::Vector3d(p[0], p[1], p[2])).z());
    }
    q[6] -= lowest + depth;  // a free base's z, after its quaternion
    u[5] = rising;           // its vertical velocity, after the angular ones
    workspace.setQ(q);
    workspace.setU(u);
  }

  Sums Forces(GroundContact& contact) {
    Sums sums;
    contact.calcForces(workspace, sums.generalized, sums.stiffness, sums.damping);
    return sums;
  }
};

// Half a millimetre deep and rising at 0.6 m/s: Hunt–Crossley gives each point 2e6·(5e-4)^1.5·(1 − 0.9)
// = 2.2 N, but its tangent, −∂f/∂δ = 6.7 kN/m, takes 4.0 N off over a 1 ms step: −1.8 N. Every point is
// released, the step's sums are left with nothing of the floor, and since the soles are off the floor at
// the step's end (0.6 mm up) the released points get nothing either.
TEST_F(GroundContactTest, ASoleLeavingFastIsReleasedNotPulled) {
  Place(5e-4, 0.6);
  GroundContact contact(model, map.feet, GroundContactOptions{});
  Sums sums = Forces(contact);
  const double h = 1e-3;
  const Eigen::VectorXd udot = Eigen::VectorXd::Zero(model.nu());
  ASSERT_GT(sums.generalized[5], 8 * 2.0) << "the points push at the step's start";
  for (const Eigen::Vector3d& force : contact.appliedFootForce(workspace.getU(), udot, h)) {
    EXPECT_LT(force.z(), -4 * 1.5) << "the tangent would pull (about -1.8 N a point)";
  }
  EXPECT_EQ(contact.releasePullingPoints(workspace.getU(), udot, h, sums.generalized, sums.stiffness, sums.damping), 8);
  EXPECT_LT(sums.generalized.norm(), 1e-9);
  EXPECT_LT(sums.stiffness.norm(), 1e-6);
  EXPECT_LT(sums.damping.norm(), 1e-9);
  const Eigen::VectorXd& released = contact.releasedForces(workspace.getU(), udot, h, [&](const Eigen::VectorXd& force, Eigen::VectorXd& response) {
    workspace.calcMassInverseTimes(force, response);
  });
  EXPECT_EQ(released.norm(), 0.0);
  for (const Eigen::Vector3d& force : contact.appliedFootForce(workspace.getU(), udot, h)) EXPECT_EQ(force.norm(), 0.0);
  // Released once: asking again releases nothing.
  EXPECT_EQ(contact.releasePullingPoints(workspace.getU(), udot, h, sums.generalized, sums.stiffness, sums.damping), 0);
}

// A touchdown at 2.6 m/s, 1.5 mm deep, with the step's solve stopping it at 3000 m/s² (the soles' damping
// overshooting): the tangent ends at about −180 N a point. Released outright the soles would fall through
// the floor for the step; instead each gets the constant force Hunt–Crossley gives at the end state that
// force leads to. Checked by the test's own arithmetic: the step's end from the free body's response to
// the released forces (A u̇ = Σ J_pᵀ F_p), each point's Hunt–Crossley force there, summed per foot.
TEST_F(GroundContactTest, ASoleLandingHardGetsTheForceItsEndStateGives) {
  Place(1.5e-3, -2.6);
  GroundContact contact(model, map.feet, GroundContactOptions{});
  Sums sums = Forces(contact);
  const double h = 1e-3;
  Eigen::VectorXd stopping = Eigen::VectorXd::Zero(model.nu());
  stopping[5] = 3000.0;
  for (const Eigen::Vector3d& force : contact.appliedFootForce(workspace.getU(), stopping, h)) EXPECT_LT(force.z(), -4 * 150.0);
  ASSERT_EQ(contact.releasePullingPoints(workspace.getU(), stopping, h, sums.generalized, sums.stiffness, sums.damping), 8);
  // Without the floor nothing acts on the body this step (no gravity in this check): u̇ = 0.
  const Eigen::VectorXd free = Eigen::VectorXd::Zero(model.nu());
  const auto response = [&](const Eigen::VectorXd& force, Eigen::VectorXd& out) { workspace.calcMassInverseTimes(force, out); };
  const Eigen::VectorXd released = contact.releasedForces(workspace.getU(), free, h, response);
  Eigen::VectorXd udot;
  response(released, udot);
  const std::vector<Eigen::Vector3d> applied = contact.appliedFootForce(workspace.getU(), udot, h);
  Eigen::Matrix<double, 6, Eigen::Dynamic> jacobian(6, model.nu());
  for (size_t f = 0; f < map.feet.size(); ++f) {
    const int link = model.findLinkIndex(map.feet[f].link);
    double expected = 0;
    for (const std::array<double, 3>& p : map.feet[f].sole_points) {
      const Eigen::Vector3d local(p[0], p[1], p[2]);
      workspace.calcFrameJacobian(link, local, jacobian);
      const double depth = -(workspace.findLinkPose(link) * local).z();
      const double rising = (jacobian.row(5) * (workspace.getU() + h * udot)).value();
      const double end_depth = depth - h * rising, hc = 1.0 - 1.5 * 1.0 * rising;
      expected += end_depth > 0 && hc > 0 ? 2e6 * std::pow(end_depth, 1.5) * hc : 0.0;
    }
    EXPECT_GT(applied[f].z(), 100.0) << "the landing sole is stopped by the floor";
    EXPECT_NEAR(applied[f].z(), expected, 1e-6 * expected) << map.feet[f].side;
    EXPECT_EQ(applied[f].head<2>().norm(), 0.0) << "a sole coming straight down, anchored where it touched: no friction";
  }
}

// Rising slowly (0.1 m/s) the tangent stays above zero: nothing is released and the sums are untouched.
TEST_F(GroundContactTest, ASolePressingOrRisingSlowlyKeepsItsForce) {
  Place(5e-4, 0.1);
  GroundContact contact(model, map.feet, GroundContactOptions{});
  Sums sums = Forces(contact);
  const Sums kept = sums;
  const Eigen::VectorXd udot = Eigen::VectorXd::Zero(model.nu());
  EXPECT_EQ(contact.releasePullingPoints(workspace.getU(), udot, 1e-3, sums.generalized, sums.stiffness, sums.damping), 0);
  EXPECT_EQ(sums.generalized, kept.generalized);
  EXPECT_EQ(sums.stiffness, kept.stiffness);
  double vertical = 0;
  for (const Eigen::Vector3d& force : contact.appliedFootForce(workspace.getU(), udot, 1e-3)) vertical += force.z();
  EXPECT_GT(vertical, 0.0);
}

// A robot map with more sole points than the released points' fixed-size solve holds is refused, naming
// the count and the limit, not run with storage that overflows.
TEST_F(GroundContactTest, ARobotMapWithTooManySolePointsIsRefused) {
  std::vector<RobotFoot> feet = map.feet;
  while (feet[0].sole_points.size() + feet[1].sole_points.size() <= 32) feet[0].sole_points.push_back({0.0, 0.0, -0.035});
  try {
    GroundContact contact(model, feet, GroundContactOptions{});
    ADD_FAILURE() << "33 sole points accepted";
  } catch (const UsageError& error) {
    EXPECT_NE(std::string(error.what()).find("33 sole points"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("at most 32"), std::string::npos) << error.what();
  }
}

}  // namespace
}  // namespace syn
