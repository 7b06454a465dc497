// Ground mode's held feet (stages/simulate/stance_feet.h): how far a held sole turned and moved over the
// source's contact phase, against poses set by hand on a G1 standing on both feet.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>

#include <Eigen/Geometry>

#include "common/model.h"
#include "common/robot_map.h"
#include "stages/simulate/stance_feet.h"
#include "tests/support/demo_motion.h"
#include "tests/support/shared_data.h"
#include "tests/support/standing_pose.h"

namespace syn {
namespace {

class HeldPhases : public ::testing::Test {
 protected:
  HeldPhases()
      : model(Model::Load(testing::SourcePath(testing::kG1Urdf))),
        map(LoadRobotMap(testing::SourcePath(testing::kG1Map))),
        workspace(model),
        standing(testing::StandingZeroPose(model, map)) {}

  // The standing pose turned by `yaw` about the vertical through the ground origin and moved by `offset`:
  // the free base's quaternion (w, x, y, z) and position lead q.
  Eigen::VectorXd Moved(double yaw, const Eigen::Vector3d& offset) const {
    Eigen::VectorXd q = standing;
    const Eigen::Quaterniond turn(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
    const Eigen::Quaterniond base = turn * Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
    q[0] = base.w(), q[1] = base.x(), q[2] = base.y(), q[3] = base.z();
    q.segment<3>(4) = turn * Eigen::Vector3d(q.segment<3>(4)) + offset;
    return q;
  }

  // Where a foot's sole centre is for q (ground x, y).
  Eigen::Vector2d SoleCentre(const Eigen::VectorXd& q, size_t foot) {
    workspace.setQ(q);
    Eigen::Vector3d centre = Eigen::Vector3d::Zero();
    for (const auto& p : map.feet[foot].sole_points) centre += Eigen::Vector3d(p[0], p[1], p[2]);
    centre /= static_cast<double>(map.feet[foot].sole_points.size());
    return (workspace.findLinkPose(model.findLinkIndex(map.feet[foot].link)) * centre).head<2>();
  }

  int Update(StanceFeet& feet, const Eigen::VectorXd& q, int64_t planted, const double* reference_heading = nullptr) {
    workspace.setQ(q);
    workspace.setU(Eigen::VectorXd::Zero(model.nu()));  // at rest (the hold's rows need the velocities set)
    const int64_t flags[2] = {planted, planted};
    return feet.update(workspace, flags, reference_heading);
  }

  // A foot's heading (its link's x axis about the vertical) for q.
  double Heading(const Eigen::VectorXd& q, size_t foot) {
    workspace.setQ(q);
    const Eigen::Matrix3d rotation = workspace.findLinkPose(model.findLinkIndex(map.feet[foot].link)).linear();
    return std::atan2(rotation(1, 0), rotation(0, 0));
  }

  Model model;
  RobotMap map;
  Workspace workspace;
  Eigen::VectorXd standing;
};

TEST_F(HeldPhases, ATurnWhileHeldIsMeasuredFromThePhasesStart) {
  StanceFeet feet(model, map.feet, StanceFeetOptions{});
  feet.reservePhases(8);
  EXPECT_EQ(Update(feet, standing, 1), 2);
  const double yaw = 10.0 * M_PI / 180.0;
  const Eigen::VectorXd turned = Moved(yaw, Eigen::Vector3d::Zero());
  EXPECT_EQ(Update(feet, turned, 1), 2);
  // Still open: the phases count as they stand.
  StanceFeet::PhaseDrift drift = feet.phaseDrift();
  EXPECT_EQ(drift.phases, 2);
  EXPECT_NEAR(drift.largest_turn, yaw, 1e-9);
  EXPECT_NEAR(drift.median_turn, yaw, 1e-9);
  // The source lifts both feet: the phases close with the largest turn and move they saw.
  EXPECT_EQ(Update(feet, standing, 0), 0);
  drift = feet.phaseDrift();
  EXPECT_EQ(drift.phases, 2);
  EXPECT_NEAR(drift.largest_turn, yaw, 1e-9);
  const double left = (SoleCentre(turned, 0) - SoleCentre(standing, 0)).norm();
  const double right = (SoleCentre(turned, 1) - SoleCentre(standing, 1)).norm();
  EXPECT_GT(std::max(left, right), 0.01);  // the feet are 10-12 cm off the turn's axis
  EXPECT_NEAR(drift.largest_move, std::max(left, right), 1e-9);
}

// A hold that lapses (the sole lifted past the touch height) re-anchors where the foot comes back down; the
// phase's measure still counts from where the phase began, so a foot creeping hold by hold is seen.
TEST_F(HeldPhases, ACreepAcrossALapsedHoldCountsFromThePhasesStart) {
  StanceFeet feet(model, map.feet, StanceFeetOptions{});
  feet.reservePhases(8);
  EXPECT_EQ(Update(feet, standing, 1), 2);
  EXPECT_EQ(Update(feet, Moved(0, {0.004, 0, 0.01}), 1), 0);  // 1 cm up: no sole touches, no hold
  EXPECT_EQ(Update(feet, Moved(0, {0.008, 0, 0}), 1), 2);     // down again 8 mm on: held anew there
  EXPECT_EQ(Update(feet, Moved(0, {0.012, 0, 0}), 1), 2);
  const StanceFeet::PhaseDrift drift = feet.phaseDrift();
  EXPECT_EQ(drift.phases, 2);
  EXPECT_NEAR(drift.largest_move, 0.012, 1e-9);
  EXPECT_NEAR(drift.median_move, 0.012, 1e-9);
  EXPECT_NEAR(drift.largest_turn, 0.0, 1e-9);
}

// A landing is measured once, at its phase's first hold, against the reference's heading for that phase:
// the turn either way across ±180°, what the foot does later in the phase not counted, and a phase the
// reference gives no heading (NaN) not a landing.
TEST_F(HeldPhases, ALandingIsMeasuredAtItsFirstHoldAgainstTheReferenceHeading) {
  StanceFeet feet(model, map.feet, StanceFeetOptions{});
  feet.reservePhases(8);
  const double degree = M_PI / 180.0;
  const Eigen::VectorXd turned = Moved(170 * degree, Eigen::Vector3d::Zero());
  // The left foot's reference 25° short of where it landed, the right's 15° past it across ±180°.
  const double references[2] = {Heading(turned, 0) - 25 * degree, std::remainder(Heading(turned, 1) + 15 * degree, 2 * M_PI)};
  ASSERT_GT(std::abs(Heading(turned, 1)) + 15 * degree, M_PI) << "the right foot's reference should wrap";
  EXPECT_EQ(Update(feet, turned, 1, references), 2);
  EXPECT_EQ(Update(feet, Moved(175 * degree, Eigen::Vector3d::Zero()), 1, references), 2);  // turns on while held
  StanceFeet::PhaseDrift drift = feet.phaseDrift();
  EXPECT_EQ(drift.landings, 2);
  EXPECT_NEAR(drift.largest_landing_turn, 25 * degree, 1e-9);
  EXPECT_NEAR(drift.median_landing_turn, 25 * degree, 1e-9);  // nearest rank of two (index round(0.5)): the upper
  EXPECT_NEAR(drift.largest_turn, 5 * degree, 1e-9);
  // Lifted, and put down where the reference gives no heading: a held phase, not a landing.
  EXPECT_EQ(Update(feet, turned, 0, references), 0);
  const double none[2] = {std::nan(""), std::nan("")};
  EXPECT_EQ(Update(feet, turned, 1, none), 2);
  drift = feet.phaseDrift();
  EXPECT_EQ(drift.phases, 4);
  EXPECT_EQ(drift.landings, 2);
}

// A phase the robot never stood in (the sole stayed up) is not a held phase.
TEST_F(HeldPhases, APhaseNeverHeldIsNotCounted) {
  StanceFeet feet(model, map.feet, StanceFeetOptions{});
  EXPECT_EQ(Update(feet, Moved(0, {0, 0, 0.02}), 1), 0);
  EXPECT_EQ(Update(feet, Moved(0, {0.05, 0, 0.02}), 0), 0);
  EXPECT_EQ(feet.phaseDrift().phases, 0);
  EXPECT_EQ(feet.phaseDrift().largest_move, 0.0);
}

// Heel-off: a foot whose reference is toe-down is held by its toe (the front sole points' centroid) and
// its heading, four rows, anchored where the toe was when heel-off began; the other foot keeps its six.
TEST_F(HeldPhases, AFootAtHeelOffIsHeldByItsToeAndHeading) {
  StanceFeet feet(model, map.feet, StanceFeetOptions{.touch_height = 0.01});
  const int64_t planted[2] = {1, 1};
  const char left_heel_off[2] = {1, 0};
  workspace.setQ(standing);
  workspace.setU(Eigen::VectorXd::Zero(model.nu()));
  ASSERT_EQ(feet.update(workspace, planted, nullptr, left_heel_off), 2);
  ASSERT_EQ(feet.jacobian().rows(), 10);
  EXPECT_TRUE(feet.heldByTheToe(0));
  EXPECT_FALSE(feet.heldByTheToe(1));
  // The toe, from the map's sole points: those furthest forward.
  double front = -1e9;
  for (const auto& p : map.feet[0].sole_points) front = std::max(front, p[0]);
  Eigen::Vector3d toe = Eigen::Vector3d::Zero();
  int count = 0;
  for (const auto& p : map.feet[0].sole_points) {
    if (p[0] >= front - 1e-4) toe += Eigen::Vector3d(p[0], p[1], p[2]), ++count;
  }
  ASSERT_GE(count, 1);
  toe /= count;
  // Rows 1-3 are the toe's velocity: against a finite difference of its position along a joint-space motion.
  const int link = model.findLinkIndex(map.feet[0].link);
  Eigen::VectorXd velocity = Eigen::VectorXd::Zero(model.nu());
  for (int i = 6; i < model.nu(); ++i) velocity[i] = 0.1 * std::sin(1.0 + i);
  velocity[3] = 0.2;  // and the base translating
  const double h = 1e-6;
  Eigen::VectorXd moved = standing;
  for (int i = 6; i < model.nu(); ++i) moved[i + 1] += h * velocity[i];  // joints: q index = u index + 1
  moved[4] += h * velocity[3];
  workspace.setQ(standing);
  const Eigen::Vector3d before = workspace.findLinkPose(link) * toe;
  workspace.setQ(moved);
  const Eigen::Vector3d after = workspace.findLinkPose(link) * toe;
  const Eigen::Vector3d rows = feet.jacobian().block(1, 0, 3, model.nu()) * velocity;
  EXPECT_LT((rows - (after - before) / h).norm(), 1e-4) << rows.transpose() << " against " << ((after - before) / h).transpose();
  // Moved 1 cm forward and still at heel-off: the toe is pulled back to where heel-off began (kp 900, at
  // rest), and so is the right sole's centre; the heading row has nothing to correct.
  workspace.setQ(Moved(0.0, Eigen::Vector3d(0.01, 0, 0)));
  workspace.setU(Eigen::VectorXd::Zero(model.nu()));
  ASSERT_EQ(feet.update(workspace, planted, nullptr, left_heel_off), 2);
  const Eigen::VectorXd& wanted = feet.acceleration();
  EXPECT_NEAR(wanted[0], 0.0, 1e-9);
  EXPECT_NEAR(wanted[1], -9.0, 1e-6);
  EXPECT_NEAR(wanted[2], 0.0, 1e-6);
  EXPECT_NEAR(wanted[4 + 3], -9.0, 1e-6);
}

TEST(HeelOff, IsAToeDownTiltPastTheThreshold) {
  const auto pitched = [](double angle) { return Eigen::AngleAxisd(angle, Eigen::Vector3d::UnitY()).toRotationMatrix(); };
  // About +y a positive angle turns +x toward −z: toe down.
  EXPECT_TRUE(HeelOff(pitched(0.05), 0.03));
  EXPECT_FALSE(HeelOff(pitched(0.02), 0.03));
  EXPECT_FALSE(HeelOff(pitched(-0.05), 0.03));  // toe up: a heel strike, not a heel-off
  EXPECT_FALSE(HeelOff(Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitX()).toRotationMatrix(), 0.03));  // rolled sideways, toe level
}

}  // namespace
}  // namespace syn
