// The controller's joint-limit walls: a posture that asks a joint past its URDF limit gets the joint
// held at the limit, and without the walls the same controller drives it through (so the test can fail).
#include <gtest/gtest.h>

#include "common/model.h"
#include "stages/simulate/fixed_step_integrator.h"
#include "stages/simulate/operational_space_controller.h"
#include "tests/support/demo_motion.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

struct Extremes {
  double lowest, highest, final;
};

// 1 s at 1 kHz of the G1 (base welded, no gravity, no tasks) whose posture asks the left knee for
// `target`, starting from the URDF's default pose.
Extremes DriveKnee(double target, bool joint_limits) {
  ModelOptions model_options;
  model_options.floating_base = FloatingBase::kFixed;
  model_options.gravity = 0.0;
  const Model model = Model::Load(testing::SourcePath(testing::kG1Urdf), model_options);
  int knee = -1;
  for (const ModelJoint& joint : model.joints()) {
    if (joint.name == "left_knee_joint") knee = joint.q_index;
  }
  EXPECT_GE(knee, 0);
  ControllerOptions options;
  options.joint_limits = joint_limits;
  options.effort_limits = false;
  OperationalSpaceController controller(model, {}, options);
  FixedStepIntegrator integrator(model);
  Workspace workspace(model);
  Eigen::VectorXd q = model.defaultQ(), u = Eigen::VectorXd::Zero(model.nu()), tau, udot;
  PostureReference posture{q, u, u};
  posture.q[knee] = target;
  Extremes extremes{q[knee], q[knee], 0};
  for (int step = 0; step < 1000; ++step) {
    workspace.setQ(q);
    workspace.setU(u);
    controller.calcTorques(workspace, {}, posture, tau);
    workspace.calcForwardDynamics(tau, udot);
    integrator.step(workspace, Integrator::kSemiImplicitEuler, tau, 1e-3, &udot, q, u);
    extremes.lowest = std::min(extremes.lowest, q[knee]);
    extremes.highest = std::max(extremes.highest, q[knee]);
  }
  extremes.final = q[knee];
  return extremes;
}

double KneeLimit(bool upper) {
  const Model model = Model::Load(testing::SourcePath(testing::kG1Urdf));
  for (const ModelJoint& joint : model.joints()) {
    if (joint.name == "left_knee_joint") return upper ? model.qUpper()[joint.q_index] : model.qLower()[joint.q_index];
  }
  return 0;
}

TEST(JointLimitWalls, PostureBeyondTheLowerLimitStopsAtIt) {
  const double lower = KneeLimit(false);  // G1: −0.087 rad, the straight knee
  const Extremes walled = DriveKnee(lower - 0.4, true);
  EXPECT_GT(walled.lowest, lower - 0.01);
  EXPECT_NEAR(walled.final, lower, 0.005);
  const Extremes free = DriveKnee(lower - 0.4, false);
  EXPECT_LT(free.lowest, lower - 0.3);  // the posture alone bends it backwards
}

TEST(JointLimitWalls, PostureBeyondTheUpperLimitStopsAtIt) {
  const double upper = KneeLimit(true);
  const Extremes walled = DriveKnee(upper + 0.4, true);
  EXPECT_LT(walled.highest, upper + 0.01);
  EXPECT_NEAR(walled.final, upper, 0.005);
  EXPECT_GT(DriveKnee(upper + 0.4, false).highest, upper + 0.3);
}

}  // namespace
}  // namespace syn
