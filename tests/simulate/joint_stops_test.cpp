// The joints' mechanical stops of ground mode (joint_stops.h): a joint past its URDF limit is pushed back
// by the stop's spring and damper and never pulled, a joint inside its range feels nothing unless it
// crosses within the step, and a G1 ankle roll driven hard into its limit under the implicit step settles
// a fraction of a milliradian past it.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Cholesky>

#include "common/model.h"
#include "stages/simulate/joint_stops.h"
#include "tests/support/demo_motion.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

Model WeldedG1() {
  ModelOptions options;
  options.floating_base = FloatingBase::kFixed;
  options.gravity = 0.0;
  return Model::Load(testing::SourcePath(testing::kG1Urdf), options);
}

const ModelJoint& JointNamed(const Model& model, const std::string& name) {
  for (const ModelJoint& joint : model.joints()) {
    if (joint.name == name) return joint;
  }
  throw std::runtime_error("no joint " + name);
}

struct Forces {
  Eigen::VectorXd generalized;
  Eigen::MatrixXd stiffness, damping;
  explicit Forces(int nu) : generalized(Eigen::VectorXd::Zero(nu)), stiffness(Eigen::MatrixXd::Zero(nu, nu)), damping(Eigen::MatrixXd::Zero(nu, nu)) {}
};

TEST(JointStops, PushBackPastALimitAndNeverPull) {
  const Model model = WeldedG1();
  const ModelJoint& roll = JointNamed(model, "left_ankle_roll_joint");
  const double upper = model.qUpper()[roll.q_index], lower = model.qLower()[roll.q_index];
  const JointStopOptions options;
  const JointStops stops(model, options);
  Eigen::VectorXd q = model.defaultQ(), u = Eigen::VectorXd::Zero(model.nu());

  // Inside the range, moving fast: nothing.
  q[roll.q_index] = 0.5 * (upper + lower), u[roll.u_index] = 10.0;
  Forces inside(model.nu());
  EXPECT_EQ(stops.add(q, u, 0.0, inside.generalized, inside.stiffness, inside.damping), 0);
  EXPECT_EQ(inside.generalized.norm(), 0.0);

  // 0.01 rad past the upper limit, at rest: the spring's torque, pushing down, and its stiffness and damping
  // on the diagonal.
  q[roll.q_index] = upper + 0.01, u[roll.u_index] = 0.0;
  Forces past(model.nu());
  EXPECT_EQ(stops.add(q, u, 0.0, past.generalized, past.stiffness, past.damping), 1);
  EXPECT_NEAR(past.generalized[roll.u_index], -options.stiffness * 0.01, 1e-9);
  EXPECT_EQ(past.stiffness(roll.u_index, roll.u_index), options.stiffness);
  EXPECT_EQ(past.damping(roll.u_index, roll.u_index), options.damping);
  EXPECT_NEAR(stops.worstExcess(q), 0.01, 1e-12);

  // Past it but leaving fast: the damper would pull it back out, so the stop gives nothing.
  u[roll.u_index] = -options.stiffness * 0.01 / options.damping * 2.0;
  Forces leaving(model.nu());
  EXPECT_EQ(stops.add(q, u, 0.0, leaving.generalized, leaving.stiffness, leaving.damping), 0);
  EXPECT_EQ(leaving.generalized[roll.u_index], 0.0);

  // Still 0.01 rad inside but a 1 ms step from crossing at 20 rad/s: engaged ahead of the crossing, its
  // stiffness and damping in the implicit step (its spring does not yet push); moving away, not engaged.
  q[roll.q_index] = upper - 0.01, u[roll.u_index] = 20.0;
  Forces approaching(model.nu());
  EXPECT_EQ(stops.add(q, u, 1e-3, approaching.generalized, approaching.stiffness, approaching.damping), 1);
  EXPECT_LE(approaching.generalized[roll.u_index], 0.0);
  EXPECT_EQ(approaching.stiffness(roll.u_index, roll.u_index), options.stiffness);
  u[roll.u_index] = -20.0;
  Forces away(model.nu());
  EXPECT_EQ(stops.add(q, u, 1e-3, away.generalized, away.stiffness, away.damping), 0);
  u[roll.u_index] = 20.0;
  Forces no_step(model.nu());
  EXPECT_EQ(stops.add(q, u, 0.0, no_step.generalized, no_step.stiffness, no_step.damping), 0);

  // Mirrored at the lower limit: pushes up.
  q[roll.q_index] = lower - 0.02, u[roll.u_index] = 0.0;
  Forces below(model.nu());
  EXPECT_EQ(stops.add(q, u, 0.0, below.generalized, below.stiffness, below.damping), 1);
  EXPECT_NEAR(below.generalized[roll.u_index], options.stiffness * 0.02, 1e-9);
}

// A 50 N·m torque (G1's ankle roll effort) held for 0.2 s at 1 kHz on the ankle roll, starting at rest on
// its limit, the stop in a linearly implicit step as syn-simulate's ground mode takes it
// ((A + h B + h² K) u̇ = τ + f − b − h K u): the joint comes to rest at the limit plus 50 / k; without the
// stop it runs far past. (The light foot, 50 rad/s after its first step, overshoots by 0.15 rad before the
// stop catches it: a stop engages a step late. On the CMU walks that stay up the joints stay within 1.2°
// of their limits: simulation_test.cpp.)
TEST(JointStops, HoldAJointDrivenIntoItsLimit) {
  const Model model = WeldedG1();
  const ModelJoint& roll = JointNamed(model, "left_ankle_roll_joint");
  const double upper = model.qUpper()[roll.q_index];
  const JointStopOptions options;
  const JointStops stops(model, options);
  const double h = 1e-3, torque = 50.0;
  for (const bool with_stops : {true, false}) {
    SCOPED_TRACE(with_stops ? "with stops" : "without");
    Workspace workspace(model);
    Eigen::VectorXd q = model.defaultQ(), u = Eigen::VectorXd::Zero(model.nu()), tau = Eigen::VectorXd::Zero(model.nu());
    q[roll.q_index] = upper;
    tau[roll.u_index] = torque;
    double highest = q[roll.q_index];
    Eigen::MatrixXd mass;
    Eigen::VectorXd bias;
    for (int step = 0; step < 200; ++step) {
      workspace.setQ(q);
      workspace.setU(u);
      Forces stop(model.nu());
      if (with_stops) stops.add(q, u, h, stop.generalized, stop.stiffness, stop.damping);
      workspace.calcMassMatrix(mass);
      workspace.calcInverseDynamics(Eigen::VectorXd::Zero(model.nu()), bias);  // b(q, u): the velocity terms
      const Eigen::MatrixXd implicit = mass + h * stop.damping + h * h * stop.stiffness;
      const Eigen::VectorXd udot = implicit.ldlt().solve(tau + stop.generalized - bias - h * (stop.stiffness * u));
      u += h * udot;
      q += h * u;  // the welded G1's coordinates are all revolute angles
      highest = std::max(highest, q[roll.q_index]);
      if (!with_stops && q[roll.q_index] > upper + 1.0) break;  // far past: shown
    }
    if (with_stops) {
      EXPECT_NEAR(q[roll.q_index], upper + torque / options.stiffness, 1e-3);
      EXPECT_LT(highest, upper + 0.2);
    } else {
      EXPECT_GT(q[roll.q_index], upper + 1.0);
    }
  }
}

}  // namespace
}  // namespace syn
