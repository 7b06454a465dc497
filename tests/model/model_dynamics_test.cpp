// Mass matrix products, kinetic energy, inverse and forward dynamics of the
// Simbody model, checked against computations made in the test.
#include <gtest/gtest.h>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>
#include <cmath>
#include <fstream>
#include <iostream>
#include <random>
#include <unistd.h>

#include <filesystem>
#include <string>
#include <vector>

#include "common/model.h"
#include "tests/support/scratch_file.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

// The G1 is bundled (datasets/robots/unitree_g1/, byte-identical to ../shared's robots/unitree/g1_29dof.urdf),
// so every check runs on it everywhere; HRP-4C and H1 come from ../shared and are reported when absent.
const char kBundledG1[] = "datasets/robots/unitree_g1/g1_29dof.urdf";
const char* kSharedRobots[] = {"robots/humanoid_synergies/HRP4c_optitrack_model.urdf", "robots/unitree/h1.urdf"};

// The URDFs to check: the bundled G1, then each shared robot that exists (a missing one is printed).
std::vector<std::string> RobotsToCheck() {
  std::vector<std::string> paths = {testing::SourcePath(kBundledG1)};
  for (const char* robot : kSharedRobots) {
    if (std::filesystem::exists(testing::SharedPath(robot))) {
      paths.push_back(testing::SharedPath(robot));
    } else {
      std::cout << "[  NOTE    ] shared dataset absent, checked without it: " << testing::SharedPath(robot) << "\n";
    }
  }
  return paths;
}

Eigen::VectorXd RandomConfiguration(const Model& model, std::mt19937& random) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  Eigen::VectorXd q = model.defaultQ();
  int first_joint = 0;
  if (model.hasFreeBase()) {
    const Eigen::Quaterniond rotation = Eigen::Quaterniond::UnitRandom();
    q.head<4>() << rotation.w(), rotation.x(), rotation.y(), rotation.z();
    q.segment<3>(4) << unit(random), unit(random), 1.0;
    first_joint = 7;
  }
  for (int i = first_joint; i < model.nq(); ++i) {
    const double low = std::isfinite(model.qLower()[i]) ? std::max(model.qLower()[i], -2.0) : -2.0;
    const double high = std::isfinite(model.qUpper()[i]) ? std::min(model.qUpper()[i], 2.0) : 2.0;
    q[i] = low + (high - low) * unit(random);
  }
  return q;
}

Eigen::VectorXd RandomVector(int size, std::mt19937& random) {
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::VectorXd v(size);
  for (int i = 0; i < size; ++i) v[i] = normal(random);
  return v;
}

TEST(ModelDynamics, MassMatrixIsTheHessianOfKineticEnergyAndPositiveDefinite) {
  std::mt19937 random(7);
  for (const std::string& robot : RobotsToCheck()) {
    SCOPED_TRACE(robot);
    const Model model = Model::Load(robot);
    Workspace workspace(model);
    const int nu = model.nu();
    workspace.setQ(RandomConfiguration(model, random));
    // A, column by column from the O(n) product (done here only, never in the library).
    Eigen::MatrixXd mass(nu, nu);
    Eigen::VectorXd column;
    for (int j = 0; j < nu; ++j) {
      workspace.calcMassTimes(Eigen::VectorXd::Unit(nu, j), column);
      mass.col(j) = column;
    }
    EXPECT_LT((mass - mass.transpose()).norm(), 1e-9 * mass.norm());
    const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(mass);
    // HRP-4C's virtual base links weigh 1e-16 kg but sit in series with the real body: A stays positive definite.
    EXPECT_GT(eigen.eigenvalues().minCoeff(), 0.0);
    // ∂KE/∂u = A u: central differences of Simbody's kinetic energy (exact for a quadratic, up to rounding).
    const Eigen::VectorXd u = RandomVector(nu, random);
    Eigen::VectorXd momentum;
    workspace.setU(u);
    workspace.calcMomentum(momentum);
    const double step = 1e-3;
    for (int i = 0; i < nu; ++i) {
      Eigen::VectorXd plus = u, minus = u;
      plus[i] += step;
      minus[i] -= step;
      workspace.setU(plus);
      const double ke_plus = workspace.calcKineticEnergy();
      workspace.setU(minus);
      const double ke_minus = workspace.calcKineticEnergy();
      EXPECT_NEAR((ke_plus - ke_minus) / (2 * step), momentum[i], 1e-6 * (1 + std::abs(momentum[i]))) << i;
    }
    workspace.setU(u);
    EXPECT_NEAR(workspace.calcKineticEnergy(), 0.5 * u.dot(mass * u), 1e-9 * (1 + u.dot(mass * u)));
    // A⁻¹ (A v) = v.
    Eigen::VectorXd back;
    workspace.calcMassInverseTimes(mass * u, back);
    EXPECT_LT((back - u).norm(), 1e-8 * u.norm());
  }
}

TEST(ModelDynamics, InverseDynamicsAtRestEqualsGravityTorques) {
  std::mt19937 random(11);
  for (const std::string& robot : RobotsToCheck()) {
    SCOPED_TRACE(robot);
    const Model model = Model::Load(robot);
    Workspace workspace(model);
    const int nu = model.nu();
    const Eigen::VectorXd q = RandomConfiguration(model, random);
    workspace.setQ(q);
    workspace.setU(Eigen::VectorXd::Zero(nu));
    Eigen::VectorXd tau;
    workspace.calcInverseDynamics(Eigen::VectorXd::Zero(nu), tau);
    // Independent: g(q) = ∂V/∂q in velocity coordinates, V = Σ m g z_com, by central differences of
    // the potential energy computed from link poses (the link COMs read from the model's FK).
    // Here with the whole-body COM: V = M g z_com, perturbing q along each velocity direction.
    const double total = model.totalMass();
    const auto potential = [&](const Eigen::VectorXd& configuration) {
      workspace.setQ(configuration);
      return total * model.gravity() * workspace.findCenterOfMass().z();
    };
    const double step = 1e-6;
    Eigen::Matrix<double, 6, Eigen::Dynamic> jacobian;
    for (int i = 0; i < nu; ++i) {
      Eigen::VectorXd plus = q, minus = q;
      if (model.hasFreeBase() && i < 3) {
        // Rotate the base about ground axis i.
        const Eigen::Quaterniond base(q[0], q[1], q[2], q[3]);
        const Eigen::Quaterniond turn_plus(Eigen::AngleAxisd(step, Eigen::Vector3d::Unit(i)));
        const Eigen::Quaterniond turn_minus(Eigen::AngleAxisd(-step, Eigen::Vector3d::Unit(i)));
        const Eigen::Quaterniond p = turn_plus * base, m = turn_minus * base;
        plus.head<4>() << p.w(), p.x(), p.y(), p.z();
        minus.head<4>() << m.w(), m.x(), m.y(), m.z();
      } else {
        const int qi = model.hasFreeBase() ? i + 1 : i;
        plus[qi] += step;
        minus[qi] -= step;
      }
      const double expected = (potential(plus) - potential(minus)) / (2 * step);
      EXPECT_NEAR(tau[i], expected, 1e-6 * (1 + std::abs(expected))) << model.velocityNames()[static_cast<size_t>(i)];
    }
    // Forward dynamics of the gravity torques: the robot stays at rest.
    workspace.setQ(q);
    workspace.setU(Eigen::VectorXd::Zero(nu));
    Eigen::VectorXd udot;
    workspace.calcForwardDynamics(tau, udot);
    EXPECT_LT(udot.cwiseAbs().maxCoeff(), 1e-8);
  }
}

TEST(ModelDynamics, ForwardDynamicsInvertsInverseDynamics) {
  std::mt19937 random(5);
  for (const std::string& robot : RobotsToCheck()) {
    SCOPED_TRACE(robot);
    const Model model = Model::Load(robot);
    Workspace workspace(model);
    workspace.setQ(RandomConfiguration(model, random));
    workspace.setU(RandomVector(model.nu(), random));
    const Eigen::VectorXd udot = RandomVector(model.nu(), random);
    Eigen::VectorXd tau, back;
    workspace.calcInverseDynamics(udot, tau);
    workspace.calcForwardDynamics(tau, back);
    EXPECT_LT((back - udot).cwiseAbs().maxCoeff(), 1e-8 * (1 + udot.cwiseAbs().maxCoeff()));
  }
}

TEST(ModelDynamics, FrameJacobianMatchesFiniteDifferencesOfKinematics) {
  std::mt19937 random(3);
  const Model model = Model::Load(testing::SourcePath(kBundledG1));
  Workspace workspace(model);
  const Eigen::VectorXd q = RandomConfiguration(model, random);
  const int hand = model.findLinkIndex("left_rubber_hand");
  ASSERT_GE(hand, 0);
  const Eigen::Vector3d point(0.05, 0.01, -0.02);
  workspace.setQ(q);
  Eigen::Matrix<double, 6, Eigen::Dynamic> jacobian;
  workspace.calcFrameJacobian(hand, point, jacobian);
  const double step = 1e-6;
  for (int i = 6; i < model.nu(); ++i) {  // joint columns: u = q̇
    Eigen::VectorXd plus = q, minus = q;
    plus[i + 1] += step;
    minus[i + 1] -= step;
    workspace.setQ(plus);
    const Eigen::Isometry3d a = workspace.findLinkPose(hand);
    workspace.setQ(minus);
    const Eigen::Isometry3d b = workspace.findLinkPose(hand);
    const Eigen::Vector3d linear = (a * point - b * point) / (2 * step);
    const Eigen::AngleAxisd turn(a.linear() * b.linear().transpose());
    const Eigen::Vector3d angular = turn.angle() * turn.axis() / (2 * step);
    EXPECT_LT((linear - jacobian.col(i).tail<3>()).norm(), 1e-6) << i;
    EXPECT_LT((angular - jacobian.col(i).head<3>()).norm(), 1e-6) << i;
  }
}

// A hand-computable body: a fixed child merged into its parent must carry its mass properties along.
TEST(ModelDynamics, FixedJointMergeCombinesMassProperties) {
  const testing::ScratchFile urdf("merge", ".urdf", R"(<robot name="merge">
  <link name="base"><inertial><mass value="1"/><inertia ixx="0.1" iyy="0.1" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <link name="tip"><inertial><origin xyz="0.5 0 0" rpy="0 0 0"/><mass value="2"/>
    <inertia ixx="0.2" iyy="0.3" izz="0.4" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="weld" type="fixed"><parent link="base"/><child link="tip"/><origin xyz="0.5 0 0" rpy="0 0 1.5707963267948966"/></joint>
</robot>)");
  const Model model = Model::Load(urdf.path());
  ASSERT_TRUE(model.hasFreeBase());
  Workspace workspace(model);
  workspace.setQ(model.defaultQ());
  // The tip's COM: 0.5 along the joint's x, then 0.5 along the tip's own x = base y.
  const Eigen::Vector3d tip_com(0.5, 0.5, 0.0);
  EXPECT_LT((workspace.findCenterOfMass() - tip_com * 2.0 / 3.0).norm(), 1e-12);
  // Spinning about ground z through the base origin: KE = ½ ω² (0.1 + 0.4 + 2 |c_xy|²).
  Eigen::VectorXd u = Eigen::VectorXd::Zero(6);
  u[2] = 2.0;
  workspace.setU(u);
  EXPECT_NEAR(workspace.calcKineticEnergy(), 0.5 * 4.0 * (0.1 + 0.4 + 2.0 * 0.5), 1e-12);
  // About ground x: the tip's principal axes are turned 90° about z, so its x moment is 0.3; c_y = 0.5, c_z = 0.
  u.setZero();
  u[0] = 2.0;
  workspace.setU(u);
  EXPECT_NEAR(workspace.calcKineticEnergy(), 0.5 * 4.0 * (0.1 + 0.3 + 2.0 * 0.25), 1e-12);
  EXPECT_DOUBLE_EQ(model.totalMass(), 3.0);
}

TEST(ModelDynamics, MassTimesAtAGivenConfigurationEqualsSimbodysMultiplyByM) {
  // calcMassTimesAt walks the tree itself (syn-evaluate's Monte-Carlo loop); Simbody's multiplyByM after
  // setQ is the reference. HRP-4C covers prismatic joints and a fixed base, G1 and H1 a free base.
  std::mt19937 random(23);
  for (const std::string& robot : RobotsToCheck()) {
    SCOPED_TRACE(robot);
    const Model model = Model::Load(robot);
    Workspace workspace(model), reference(model);
    workspace.setQ(RandomConfiguration(model, random));
    const Eigen::VectorXd before = workspace.getQ();
    Eigen::VectorXd fast, simbody;
    for (int trial = 0; trial < 20; ++trial) {
      Eigen::VectorXd q = RandomConfiguration(model, random);
      if (model.hasFreeBase()) {
        q.segment<3>(4) *= 5.0;                    // metres away from the origin, as a long walk gets
        if (trial % 2) q.head<4>() *= 1.3;         // an unnormalised quaternion is normalised, as setQ does
      }
      const Eigen::VectorXd v = RandomVector(model.nu(), random);
      workspace.calcMassTimesAt(q, v, fast);
      reference.setQ(q);
      reference.calcMassTimes(v, simbody);
      ASSERT_EQ(fast.size(), model.nu());
      EXPECT_LT((fast - simbody).cwiseAbs().maxCoeff(), 1e-12 * std::max(1.0, simbody.cwiseAbs().maxCoeff()))
          << "trial " << trial;
    }
    EXPECT_TRUE(workspace.getQ() == before) << "calcMassTimesAt must leave the workspace's configuration alone";
  }
}

TEST(ModelDynamics, DynamicsAtAGivenStateEqualSimbodysInverseDynamicsAndPoses) {
  // calcDynamicsAt (syn-evaluate's power and feet) against Simbody after setQ and setU: momentum,
  // inverse dynamics with gravity, and every link's pose.
  std::mt19937 random(29);
  for (const std::string& robot : RobotsToCheck()) {
    SCOPED_TRACE(robot);
    const Model model = Model::Load(robot);
    Workspace workspace(model), reference(model);
    Eigen::VectorXd momentum, tau, expected_momentum, expected_tau;
    for (int trial = 0; trial < 10; ++trial) {
      Eigen::VectorXd q = RandomConfiguration(model, random);
      if (model.hasFreeBase()) q.segment<3>(4) *= 5.0;
      const Eigen::VectorXd u = RandomVector(model.nu(), random), udot = RandomVector(model.nu(), random);
      workspace.calcDynamicsAt(q, u, udot, momentum, tau);
      reference.setQ(q);
      reference.setU(u);
      reference.calcMomentum(expected_momentum);
      reference.calcInverseDynamics(udot, expected_tau);
      EXPECT_LT((momentum - expected_momentum).cwiseAbs().maxCoeff(),
                1e-12 * std::max(1.0, expected_momentum.cwiseAbs().maxCoeff())) << "trial " << trial;
      EXPECT_LT((tau - expected_tau).cwiseAbs().maxCoeff(), 1e-11 * std::max(1.0, expected_tau.cwiseAbs().maxCoeff()))
          << "trial " << trial;
      for (size_t link = 0; link < model.linkNames().size(); ++link) {
        const Eigen::Isometry3d pose = workspace.findLinkPoseAtLastDynamics(static_cast<int>(link));
        const Eigen::Isometry3d expected = reference.findLinkPose(static_cast<int>(link));
        EXPECT_LT((pose.matrix() - expected.matrix()).cwiseAbs().maxCoeff(), 1e-12) << model.linkNames()[link];
      }
    }
  }
}

}  // namespace
}  // namespace syn

namespace syn {
namespace {

TEST(ModelDynamics, AnalyticFrameJacobianEqualsSimbodys) {
  std::mt19937 random(17);
  for (const std::string& robot : RobotsToCheck()) {
    SCOPED_TRACE(robot);
    const Model model = Model::Load(robot);
    Workspace workspace(model);
    workspace.setQ(RandomConfiguration(model, random));
    Eigen::Matrix<double, 6, Eigen::Dynamic> analytic, simbody;
    for (size_t link = 0; link < model.linkNames().size(); ++link) {
      const Eigen::Vector3d point(0.03, -0.02, 0.05);
      workspace.calcFrameJacobian(static_cast<int>(link), point, analytic);
      workspace.calcFrameJacobianWithSimbody(static_cast<int>(link), point, simbody);
      EXPECT_LT((analytic - simbody).cwiseAbs().maxCoeff(), 1e-12) << model.linkNames()[link];
    }
  }
}

}  // namespace
}  // namespace syn
