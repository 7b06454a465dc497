// The per-frame IK keeps knees on their bent side (branch_joints.h): a G1 frame whose feet and pelvis are
// a forward-kinematics pose with bent knees is solved back to those knees from a warm start on the wrong
// side of straight (the mirrored branch that locked the same-robot round trip's knees on −5°), and a pose
// with straight knees is still solved straight (the retry does not bend a leg that should not be).
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <string>
#include <vector>

#include "common/model.h"
#include "stages/retarget/branch_joints.h"
#include "stages/retarget/frame_ik.h"
#include "tests/retarget/g1_leg_tasks.h"

namespace syn {
namespace {

class FrameIkBranchTest : public ::testing::Test, protected testing::G1LegTasks {
 protected:
  // A standing pose with both knees at `knee`, hips and ankles pitched so the feet stay flat.
  Eigen::VectorXd Crouch(double knee) const {
    Eigen::VectorXd q = model_.defaultQ();
    q.segment<3>(4) = Eigen::Vector3d(0.1, 0.05, 0.7);
    for (const char* side : {"left", "right"}) {
      const std::string s = side;
      q[Coordinate(s + "_hip_pitch_joint")] = -knee / 2;
      q[Coordinate(s + "_knee_joint")] = knee;
      q[Coordinate(s + "_ankle_pitch_joint")] = -knee / 2;
    }
    return q;
  }

  // Exact targets: solved to convergence, with the step regularisation too small to bias the knees
  // (near straight, the feet hardly see the knee angle, and the default weights trade millimetres for it).
  static FrameIkOptions Exact() {
    FrameIkOptions options;
    options.continuity_weight = 1e-5;
    options.acceleration_weight = 0.0;
    options.function_tolerance = 1e-14;
    return options;
  }
};

TEST_F(FrameIkBranchTest, KneesBentInTheTargetsAreFoundFromTheMirroredSide) {
  const Eigen::VectorXd goal = Crouch(0.3);
  const std::vector<IkTarget> targets = TargetsAt(goal);
  // Warm start: knees just past straight the wrong way (inside G1's −0.087 rad limit), hips and ankles
  // mirrored, as a straightening leg carried through the singularity leaves them.
  Eigen::VectorXd q = goal;
  for (const char* side : {"left", "right"}) {
    const std::string s = side;
    q[Coordinate(s + "_hip_pitch_joint")] = 0.03;
    q[Coordinate(s + "_knee_joint")] = -0.06;
    q[Coordinate(s + "_ankle_pitch_joint")] = 0.03;
  }
  FrameIk ik(model_, tasks_, model_.defaultQ(), 0.0, Exact());
  ik.solve(targets, q, 0.0);
  for (const char* knee : {"left_knee_joint", "right_knee_joint"}) {
    EXPECT_NEAR(q[Coordinate(knee)], 0.3, 2e-3) << knee;
  }
  std::vector<double> position_error, angle_error;
  ik.measureErrors(targets, q, position_error, angle_error);
  for (size_t i = 0; i < tasks_.size(); ++i) {
    EXPECT_LT(position_error[i], 1e-4) << "task " << i;
    EXPECT_LT(angle_error[i], 1e-3) << "task " << i;
  }
}

TEST_F(FrameIkBranchTest, StraightKneesInTheTargetsStayStraightAndNoKneeGoesBelowZero) {
  const Eigen::VectorXd goal = Crouch(0.0);
  const std::vector<IkTarget> targets = TargetsAt(goal);
  Eigen::VectorXd q = Crouch(0.25);  // warm start bent: the retry must not keep a bent answer that costs more
  FrameIk ik(model_, tasks_, model_.defaultQ(), 0.0, Exact());
  ik.solve(targets, q, 0.0);
  const std::vector<bool> branch = BranchCoordinates(model_);
  for (const char* knee : {"left_knee_joint", "right_knee_joint"}) {
    ASSERT_TRUE(branch[static_cast<size_t>(Coordinate(knee))]) << knee;
    EXPECT_GE(q[Coordinate(knee)], 0.0) << knee;
    EXPECT_LT(q[Coordinate(knee)], 0.02) << knee;
  }
}

}  // namespace
}  // namespace syn
