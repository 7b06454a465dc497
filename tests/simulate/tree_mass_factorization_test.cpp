// The sparse LTDL factorisation of the mass matrix against Simbody's own O(n) A⁻¹ operator and A x, on
// G1 with a free and a welded base at random configurations: every solve (and the Gram matrix bᵀ A⁻¹ b
// the controller's task inertia needs) must agree to rounding, and the factor's tree must be the URDF's
// (a wrong parent array gives a wrong A⁻¹ x, not a crash).
#include <random>

#include <gtest/gtest.h>

#include "common/model.h"
#include "stages/simulate/tree_mass_factorization.h"
#include "tests/support/demo_motion.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

void ExpectSolvesMatchSimbody(const Model& model, uint32_t seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Workspace workspace(model);
  TreeMassFactorization mass(model);
  for (int trial = 0; trial < 5; ++trial) {
    Eigen::VectorXd q = model.defaultQ();
    for (int i = model.hasFreeBase() ? 4 : 0; i < model.nq(); ++i) q[i] += uniform(random);
    if (model.hasFreeBase()) q.head<4>() = Eigen::Vector4d(uniform(random), uniform(random), uniform(random), uniform(random)).normalized();
    workspace.setQ(q);
    mass.factor(workspace);
    // The tree's composite-rigid-body A against Simbody's calcM.
    Eigen::MatrixXd ours, simbody;
    workspace.calcMassMatrix(ours);
    workspace.calcMassMatrixWithSimbody(simbody);
    EXPECT_LT((ours - simbody).norm(), 1e-12 * simbody.norm()) << "trial " << trial;
    Eigen::MatrixXd right_sides(model.nu(), 3), reference(model.nu(), 3);
    for (Eigen::Index c = 0; c < right_sides.cols(); ++c) {
      Eigen::VectorXd b(model.nu()), x;
      for (int i = 0; i < model.nu(); ++i) b[i] = uniform(random);
      right_sides.col(c) = b;
      workspace.calcMassInverseTimes(b, x);
      reference.col(c) = x;
      Eigen::VectorXd solved = b;
      mass.solveInPlace(solved);
      EXPECT_LT((solved - x).norm(), 1e-9 * x.norm()) << "trial " << trial << " column " << c;
      // And back: A (A⁻¹ b) = b through Simbody's multiplyByM.
      Eigen::VectorXd back;
      workspace.calcMassTimes(solved, back);
      EXPECT_LT((back - b).norm(), 1e-9 * b.norm());
    }
    Eigen::MatrixXd rows = right_sides.transpose();
    mass.solveRowsInPlace(rows);  // every row at once: bᵀ A⁻¹
    EXPECT_LT((rows.transpose() - reference).norm(), 1e-9 * reference.norm());
    // With the Gram matrix bᵀ A⁻¹ b, formed from the half-way point of the solve: against the product of
    // the right sides with Simbody's A⁻¹ b, and symmetric to the last bit.
    Eigen::MatrixXd gram_rows = right_sides.transpose(), gram;
    mass.solveRowsInPlace(gram_rows, gram);
    EXPECT_LT((gram_rows.transpose() - reference).norm(), 1e-9 * reference.norm());
    const Eigen::MatrixXd gram_reference = right_sides.transpose() * reference;
    EXPECT_LT((gram - gram_reference).norm(), 1e-9 * gram_reference.norm()) << "trial " << trial;
    EXPECT_EQ(gram, gram.transpose());
  }
}

TEST(TreeMassFactorization, MatchesSimbodyOnFreeBaseG1) {
  ExpectSolvesMatchSimbody(Model::Load(testing::SourcePath(testing::kG1Urdf)), 3);
}

TEST(TreeMassFactorization, MatchesSimbodyOnWeldedG1) {
  ModelOptions options;
  options.floating_base = FloatingBase::kFixed;
  ExpectSolvesMatchSimbody(Model::Load(testing::SourcePath(testing::kG1Urdf), options), 5);
}

TEST(TreeMassFactorization, ParentsFollowTheTree) {
  const Model model = Model::Load(testing::SourcePath(testing::kG1Urdf));
  const TreeMassFactorization mass(model);
  // The free base's six velocities are a chain from the root; each leg's first joint hangs from the
  // base's last velocity, and a knee from its hip.
  for (int i = 0; i < 6; ++i) EXPECT_EQ(mass.parents()[static_cast<size_t>(i)], i - 1);
  int hip_roll = -1, hip_pitch = -1, knee = -1;
  for (const ModelJoint& joint : model.joints()) {
    if (joint.name == "left_hip_pitch_joint") hip_pitch = joint.u_index;
    if (joint.name == "left_hip_roll_joint") hip_roll = joint.u_index;
    if (joint.name == "left_knee_joint") knee = joint.u_index;
  }
  ASSERT_GE(knee, 0);
  EXPECT_EQ(mass.parents()[static_cast<size_t>(hip_pitch)], 5);
  EXPECT_EQ(mass.parents()[static_cast<size_t>(hip_roll)], hip_pitch);
  EXPECT_GT(knee, hip_roll);
}

}  // namespace
}  // namespace syn
