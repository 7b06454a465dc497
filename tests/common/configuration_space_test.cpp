#include "common/configuration_space.h"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>

#include <Eigen/Geometry>

namespace syn {
namespace {

// A free-base configuration: quaternion (w, x, y, z), position, two joints.
Eigen::VectorXd FreeBaseQ(const Eigen::Quaterniond& base, double joint) {
  Eigen::VectorXd q(9);
  q << base.w(), base.x(), base.y(), base.z(), 0.1, -0.2, 0.9, joint, -joint;
  return q;
}

const Eigen::Vector3d kAxis = Eigen::Vector3d(0.3, -0.5, 0.8).normalized();

TEST(ConfigurationSpace, InterpolateIsLinearWithoutAFreeBase) {
  const ConfigurationShape shape = ConfigurationShape::Of(false, 3);
  const Eigen::Vector3d q0(0.5, -1.0, 2.0), q1(1.5, 1.0, -2.0);
  Eigen::VectorXd q;
  Interpolate(shape, q0, q1, 0.25, q);
  EXPECT_NEAR(q[0], 0.75, 1e-15);
  EXPECT_NEAR(q[1], -0.5, 1e-15);
  EXPECT_NEAR(q[2], 1.0, 1e-15);
}

TEST(ConfigurationSpace, InterpolateTurnsTheBaseAlongTheGeodesicToTheNearerSign) {
  const ConfigurationShape shape = ConfigurationShape::Of(true, 9);
  const Eigen::Quaterniond a(Eigen::AngleAxisd(0.4, kAxis)), b(Eigen::AngleAxisd(0.55, kAxis));
  const double s = 0.3;
  Eigen::VectorXd q;
  Interpolate(shape, FreeBaseQ(a, 0.2), FreeBaseQ(b, 0.6), s, q);
  EXPECT_NEAR(q.head<4>().norm(), 1.0, 1e-15);
  // Independent: slerp turns by s × Ω (Ω = 0.15 rad) about the same axis; normalised lerp about the same
  // axis by 2 atan2(s sin(Ω/2), 1 − s + s cos(Ω/2)), 1.2e-5 rad less here.
  const Eigen::AngleAxisd turned(Eigen::Quaterniond(q[0], q[1], q[2], q[3]) * a.conjugate());
  EXPECT_NEAR((turned.axis() - kAxis).norm(), 0.0, 1e-12);
  const double half = std::atan2(s * std::sin(0.075), 1 - s + s * std::cos(0.075));
  EXPECT_NEAR(turned.angle(), 2 * half, 1e-14);
  EXPECT_NEAR(turned.angle(), s * 0.15, 2e-5);
  EXPECT_NEAR(q[7], 0.32, 1e-15);  // joints and position linear
  EXPECT_NEAR(q[4], 0.1, 1e-15);

  // −b is the same rotation: the same result, to the bit.
  const Eigen::Quaterniond minus_b(-b.w(), -b.x(), -b.y(), -b.z());
  Eigen::VectorXd q_minus;
  Interpolate(shape, FreeBaseQ(a, 0.2), FreeBaseQ(minus_b, 0.6), s, q_minus);
  EXPECT_EQ(q_minus, q);
}

TEST(ConfigurationSpace, InterpolateUnnormalizedLeavesTheBaseOnTheChord) {
  const ConfigurationShape shape = ConfigurationShape::Of(true, 9);
  const Eigen::Quaterniond a(Eigen::AngleAxisd(0.4, kAxis)), b(Eigen::AngleAxisd(1.4, kAxis));
  const Eigen::VectorXd q0 = FreeBaseQ(a, 0.2), q1 = FreeBaseQ(b, 0.6);
  const double s = 0.5;
  Eigen::VectorXd chord(9), q;
  InterpolateUnnormalized(shape, q0.data(), q1.data(), s, chord.data());
  Interpolate(shape, q0, q1, s, q);
  // Independent: |(1 − s) a + s b|² = (1 − s)² + s² + 2 s (1 − s) cos(Ω/2), Ω = 1 rad between a and b.
  EXPECT_NEAR(chord.head<4>().squaredNorm(), 0.5 + 0.5 * std::cos(0.5), 1e-15);
  for (int i = 0; i < 4; ++i) EXPECT_NEAR(chord[i] / chord.head<4>().norm(), q[i], 1e-15) << i;
  EXPECT_EQ(chord.tail<5>(), q.tail<5>());
}

TEST(ConfigurationSpace, CheckedInterpolateNamesTheWrongSize) {
  const ConfigurationShape shape = ConfigurationShape::Of(true, 9);
  Eigen::VectorXd q;
  try {
    Interpolate(shape, Eigen::VectorXd::Zero(8), Eigen::VectorXd::Zero(9), 0.5, q);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& error) {
    EXPECT_STREQ(error.what(), "Interpolate: q0: expected 9 values, got 8");
  }
}

// The rotation-vector Jacobians against Eigen's AngleAxis: turning by φ + δ equals turning by φ and then by
// RotationLeftJacobian(φ) δ, to first order (central differences); the inverse inverts it; CrossMatrix is ×.
TEST(ConfigurationSpace, RotationLeftJacobianIsTheTurnOfARotationVectorsChange) {
  const auto exp = [](const Eigen::Vector3d& phi) {
    const double angle = phi.norm();
    return angle > 0 ? Eigen::Matrix3d(Eigen::AngleAxisd(angle, phi / angle)) : Eigen::Matrix3d::Identity();
  };
  const Eigen::Vector3d w(0.3, -0.7, 0.2);
  EXPECT_LT((CrossMatrix(w) * Eigen::Vector3d(1.5, 0.4, -2.0) - w.cross(Eigen::Vector3d(1.5, 0.4, -2.0))).norm(), 1e-15);
  for (const Eigen::Vector3d& phi : {Eigen::Vector3d(0.0, 0.0, 0.0), Eigen::Vector3d(2e-7, -1e-7, 0.0),
                                     Eigen::Vector3d(0.4, -0.3, 0.8), Eigen::Vector3d(-1.9, 0.6, 1.2)}) {
    const Eigen::Matrix3d left = RotationLeftJacobian(phi);
    constexpr double h = 1e-6;
    for (int i = 0; i < 3; ++i) {
      const Eigen::Vector3d step = h * Eigen::Vector3d::Unit(i);
      const Eigen::AngleAxisd turn(exp(phi + step) * exp(phi - step).transpose());
      EXPECT_LT(((turn.axis() * turn.angle()) / (2 * h) - left.col(i)).norm(), 1e-8) << "phi " << phi.transpose() << ", column " << i;
    }
    EXPECT_LT((RotationLeftJacobianInverse(phi) * left - Eigen::Matrix3d::Identity()).norm(), 1e-9) << phi.transpose();
  }
}

}  // namespace
}  // namespace syn
