// Ground mode's contact-consistent torques (stages/simulate/contact_consistent_torques.h) on a G1 standing
// on both feet: a plan the soles can carry comes back unchanged, and one they cannot is taken up by the
// body with the held feet kept, better than by the base alone.
#include <gtest/gtest.h>

#include <random>
#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/LU>

#include "common/contact_forces.h"
#include "common/model.h"
#include "common/robot_map.h"
#include "stages/simulate/contact_consistent_torques.h"
#include "tests/support/demo_motion.h"
#include "tests/support/shared_data.h"
#include "tests/support/standing_pose.h"

namespace syn {
namespace {

class ContactConsistent : public ::testing::Test {
 protected:
  ContactConsistent()
      : model(Model::Load(testing::SourcePath(testing::kG1Urdf))),
        map(LoadRobotMap(testing::SourcePath(testing::kG1Map))),
        workspace(model),
        nu(model.nu()) {
    workspace.setQ(testing::StandingZeroPose(model, map));
    workspace.setU(Eigen::VectorXd::Zero(nu));  // at rest: no velocity terms in the feet's rows
    workspace.calcMassMatrix(mass);
    workspace.calcInverseDynamics(Eigen::VectorXd::Zero(nu), bias);
    for (int v = 0; v < nu; ++v) {
      (model.actuatedVelocities()[static_cast<size_t>(v)] ? actuated : base).push_back(v);
    }
    // Both feet held: their rows at the sole centres.
    Eigen::Matrix<double, 6, Eigen::Dynamic> jacobian(6, nu);
    stance.resize(12, nu);
    for (size_t f = 0; f < 2; ++f) {
      Eigen::Vector3d centre = Eigen::Vector3d::Zero();
      for (const auto& p : map.feet[f].sole_points) centre += Eigen::Vector3d(p[0], p[1], p[2]) / 4.0;
      workspace.calcFrameJacobian(model.findLinkIndex(map.feet[f].link), centre, jacobian);
      stance.middleRows(static_cast<Eigen::Index>(6 * f), 6) = jacobian;
    }
  }

  // Σ J_pᵀ f_p over the map's sole points (every foot's in order), the forces in ground.
  Eigen::VectorXd Generalized(const std::vector<Eigen::Vector3d>& forces) {
    Eigen::VectorXd out = Eigen::VectorXd::Zero(nu);
    Eigen::Matrix<double, 6, Eigen::Dynamic> jacobian(6, nu);
    size_t k = 0;
    for (const RobotFoot& foot : map.feet) {
      for (const auto& p : foot.sole_points) {
        workspace.calcFrameJacobian(model.findLinkIndex(foot.link), Eigen::Vector3d(p[0], p[1], p[2]), jacobian);
        out += jacobian.bottomRows<3>().transpose() * forces[k++];
      }
    }
    return out;
  }

  // The accelerations the torques and the planned forces give: A⁻¹ (τ + Σ J_pᵀ f_p − b − g).
  Eigen::VectorXd Accelerations(const Eigen::VectorXd& tau, const ContactForceFrame& planned) {
    return mass.ldlt().solve(tau + Generalized(planned.point_force) - bias);
  }

  ContactForceOptions ForceOptions() const {
    ContactForceOptions options;
    options.max_height = 0.002;
    return options;
  }

  const Model model;
  const RobotMap map;
  Workspace workspace;
  const int nu;
  Eigen::MatrixXd mass, stance;
  Eigen::VectorXd bias;
  std::vector<int> actuated, base;
  const int64_t planted[2] = {1, 1};
};

TEST_F(ContactConsistent, APlanTheSolesCanCarryComesBackUnchanged) {
  // Sole forces inside the cones (an eighth of the weight on each point, a little sideways), random joint
  // accelerations, and the base's accelerations those forces give: a plan that is realisable as it is.
  std::vector<Eigen::Vector3d> forces;
  const double share = model.totalMass() * model.gravity() / 8.0;
  for (int k = 0; k < 8; ++k) forces.emplace_back(0.05 * share * ((k % 3) - 1), 0.04 * share * ((k % 2) ? 1 : -1), share);
  const Eigen::VectorXd sole = Generalized(forces);
  std::mt19937 random(7);
  std::uniform_real_distribution<double> uniform(-2.0, 2.0);
  Eigen::VectorXd plan = Eigen::VectorXd::Zero(nu);
  for (int j : actuated) plan[j] = uniform(random);
  Eigen::MatrixXd base_block(base.size(), base.size());
  Eigen::VectorXd rhs(base.size());
  for (size_t r = 0; r < base.size(); ++r) {
    rhs[static_cast<Eigen::Index>(r)] = sole[base[r]] - bias[base[r]];
    for (int j : actuated) rhs[static_cast<Eigen::Index>(r)] -= mass(base[r], j) * plan[j];
    for (size_t c = 0; c < base.size(); ++c) base_block(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) = mass(base[r], base[c]);
  }
  const Eigen::VectorXd base_acceleration = base_block.ldlt().solve(rhs);
  for (size_t r = 0; r < base.size(); ++r) plan[base[r]] = base_acceleration[static_cast<Eigen::Index>(r)];

  ContactConsistentTorques torques(model, map.feet, ForceOptions(), false);
  Eigen::VectorXd tau(nu);
  torques.apply(workspace, mass, bias, plan, planted, stance, stance * plan, tau);
  for (int b : base) EXPECT_EQ(tau[b], 0.0) << "velocity " << b << ": the base has no motor";
  EXPECT_LT(torques.planned().unexplained.norm(), 1e-6 * share);
  const Eigen::VectorXd result = Accelerations(tau, torques.planned());
  EXPECT_LT((result - plan).cwiseAbs().maxCoeff(), 1e-6 * plan.cwiseAbs().maxCoeff());
  for (const Eigen::Vector3d& f : torques.planned().point_force) {
    EXPECT_GE(f.z(), 0.0);
    EXPECT_LE(f.head<2>().norm(), 0.8 * f.z() + 1e-9);
  }
}

TEST_F(ContactConsistent, WhatTheSolesCannotCarryMovesTheBodyNotTheHeldFeet) {
  // The plan drops the base at 3 g (no sole can pull it down) and holds the feet still: the soles carry
  // less than the weight, and the held feet's rows are kept far better than by the base alone taking the
  // difference (the torques before 2026-11-28, which fitted no force to a pull and kept the joints' planned
  // accelerations; computed here independently).
  Eigen::VectorXd plan = Eigen::VectorXd::Zero(nu);
  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  Eigen::Matrix<double, 6, Eigen::Dynamic> jacobian(6, nu);
  workspace.calcFrameJacobian(model.freeBaseLink(), Eigen::Vector3d::Zero(), jacobian);
  for (int b : base) plan[b] = 3.0 * model.gravity() * -up.dot(jacobian.col(b).tail<3>());  // 3 g down along the base's slides
  const Eigen::VectorXd held = Eigen::VectorXd::Zero(12);  // the feet stay where they are

  ContactConsistentTorques torques(model, map.feet, ForceOptions(), false);
  Eigen::VectorXd tau(nu);
  torques.apply(workspace, mass, bias, plan, planted, stance, held, tau);
  for (int b : base) EXPECT_EQ(tau[b], 0.0);
  double vertical = 0;
  for (const Eigen::Vector3d& f : torques.planned().point_force) vertical += f.z();
  EXPECT_LT(vertical, model.totalMass() * model.gravity());
  const Eigen::VectorXd result = Accelerations(tau, torques.planned());
  // The base alone: the joints keep the plan's accelerations, the base gets what no force gives.
  Eigen::VectorXd base_only = plan;
  Eigen::MatrixXd base_block(base.size(), base.size());
  Eigen::VectorXd rhs(base.size());
  for (size_t r = 0; r < base.size(); ++r) {
    rhs[static_cast<Eigen::Index>(r)] = -bias[base[r]];
    for (int j : actuated) rhs[static_cast<Eigen::Index>(r)] -= mass(base[r], j) * plan[j];
    for (size_t c = 0; c < base.size(); ++c) base_block(static_cast<Eigen::Index>(r), static_cast<Eigen::Index>(c)) = mass(base[r], base[c]);
  }
  const Eigen::VectorXd base_acceleration = base_block.ldlt().solve(rhs);
  for (size_t r = 0; r < base.size(); ++r) base_only[base[r]] = base_acceleration[static_cast<Eigen::Index>(r)];
  const double kept = (stance * result - held).norm(), before = (stance * base_only - held).norm();
  std::cout << "held feet's rows off by " << kept << " (base alone: " << before << ")\n";
  EXPECT_LT(kept, 0.1 * before);
}

}  // namespace
}  // namespace syn
