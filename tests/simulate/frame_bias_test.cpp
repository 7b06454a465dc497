// Workspace::calcFrameBiasAcceleration (J̇u, what each task's acceleration subtracts) against a central
// difference of J(q) u along q̇(q, u) on G1, and FixedStepIntegrator::calcQDot against it.
#include <random>

#include <gtest/gtest.h>

#include "common/model.h"
#include "stages/simulate/fixed_step_integrator.h"
#include "tests/support/demo_motion.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

TEST(FrameBias, MatchesCentralDifferenceOfJacobianTimesVelocity) {
  const Model model = Model::Load(testing::SourcePath(testing::kG1Urdf));
  Workspace workspace(model);
  FixedStepIntegrator integrator(model);
  std::mt19937 random(5);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::VectorXd q = model.defaultQ(), u(model.nu()), qdot;
  for (int i = 7; i < model.nq(); ++i) q[i] = 0.5 * uniform(random);
  for (int i = 0; i < model.nu(); ++i) u[i] = uniform(random);
  const double h = 1e-6;
  Eigen::Matrix<double, 6, Eigen::Dynamic> jacobian;
  for (const char* link : {"left_ankle_roll_link", "right_rubber_hand", "head_link", "pelvis"}) {
    const int index = model.findLinkIndex(link);
    ASSERT_GE(index, 0) << link;
    workspace.setQ(q);
    workspace.setU(u);
    const Eigen::Matrix<double, 6, 1> bias = workspace.calcFrameBiasAcceleration(index, Eigen::Vector3d::Zero());
    integrator.calcQDot(q, u, qdot);
    Eigen::Matrix<double, 6, 1> velocity[2];
    for (int side = 0; side < 2; ++side) {
      workspace.setQ(q + (side == 0 ? -h : h) * qdot);
      workspace.calcFrameJacobian(index, Eigen::Vector3d::Zero(), jacobian);
      velocity[side] = jacobian * u;
    }
    const Eigen::Matrix<double, 6, 1> difference = (velocity[1] - velocity[0]) / (2 * h);
    EXPECT_LT((bias - difference).norm(), 1e-5 * (1 + bias.norm())) << link << "\n" << bias.transpose() << "\n"
                                                                     << difference.transpose();
  }
}

}  // namespace
}  // namespace syn
