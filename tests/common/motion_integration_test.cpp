#include <gtest/gtest.h>

#include <cmath>

#include <Eigen/Geometry>

#include "common/cubic_spline.h"
#include "common/motion_integration.h"

namespace syn {
namespace {

TEST(CubicSpline, PassesThroughKnotsIsExactOnLinesAndDifferentiatesSmoothData) {
  std::vector<double> time, values;
  for (int k = 0; k <= 400; ++k) {
    const double t = 0.01 * k + 0.003 * std::sin(k);  // non-uniform knots
    time.push_back(t);
    values.insert(values.end(), {std::sin(2 * t), 3.0 - 2.0 * t});
  }
  const CubicSpline spline(time, values, 2);
  double value[2], slope[2];
  for (int k = 0; k <= 400; k += 37) {
    spline.evaluate(time[static_cast<size_t>(k)], value, nullptr);
    EXPECT_NEAR(value[0], values[static_cast<size_t>(2 * k)], 1e-14);
  }
  for (double t = 0.2; t < 3.8; t += 0.0137) {
    spline.evaluate(t, value, slope);
    EXPECT_NEAR(value[0], std::sin(2 * t), 1e-8) << t;
    EXPECT_NEAR(slope[0], 2 * std::cos(2 * t), 1e-5) << t;
    EXPECT_NEAR(value[1], 3.0 - 2.0 * t, 1e-12) << t;
    EXPECT_NEAR(slope[1], -2.0, 1e-10) << t;
  }
  // Going back in time re-seeks rather than walking off the end.
  spline.evaluate(0.05, value, nullptr);
  EXPECT_NEAR(value[1], 3.0 - 0.1, 1e-12);
  EXPECT_THROW(CubicSpline({0.0, 0.0}, {1.0, 2.0}, 1), std::invalid_argument);
}

TEST(IntegrateVelocities, ConstantTwistOfAFreeBaseIsIntegratedExactly) {
  // ω about a tilted axis and a constant linear velocity: the exponential map is exact for constant ω.
  const Eigen::Vector3d omega(0.3, -0.4, 1.2), velocity(0.5, 0.1, -0.2);
  const int frames = 241;
  Eigen::VectorXd times(frames);
  Eigen::MatrixXd u(frames, 8);
  for (int t = 0; t < frames; ++t) {
    times[t] = t / 120.0;
    u.row(t) << omega.transpose(), velocity.transpose(), 0.7, -0.2;
  }
  Eigen::VectorXd q0(9);
  const Eigen::Quaterniond start(Eigen::AngleAxisd(0.4, Eigen::Vector3d(1, 1, 0).normalized()));
  q0 << start.w(), start.x(), start.y(), start.z(), 1, 2, 3, 0.1, 0.2;
  Eigen::MatrixXd q, ground;
  IntegrateVelocities(true, q0, times, u, BaseVelocityFrame::kGround, q, ground);
  const double end = times[frames - 1];
  const Eigen::Quaterniond expected =
      Eigen::Quaterniond(Eigen::AngleAxisd(omega.norm() * end, omega.normalized())) * start;
  const Eigen::Quaterniond got(q(frames - 1, 0), q(frames - 1, 1), q(frames - 1, 2), q(frames - 1, 3));
  EXPECT_LT(got.angularDistance(expected), 1e-12);
  EXPECT_LT((q.row(frames - 1).segment<3>(4).transpose() - (Eigen::Vector3d(1, 2, 3) + velocity * end)).norm(), 1e-12);
  EXPECT_NEAR(q(frames - 1, 7), 0.1 + 0.7 * end, 1e-12);
  EXPECT_NEAR(q(frames - 1, 8), 0.2 - 0.2 * end, 1e-12);
}

TEST(IntegrateVelocities, HeadingFrameVelocitiesTurnWithThePose) {
  // Walking "forward" (+X of the heading frame) at 1 m/s from a pose facing +Y ends up moving along +Y.
  Eigen::VectorXd times = Eigen::VectorXd::LinSpaced(101, 0.0, 1.0);
  Eigen::MatrixXd u = Eigen::MatrixXd::Zero(101, 6);
  u.col(3).setOnes();
  const Eigen::Quaterniond facing_y(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  Eigen::VectorXd q0(7);
  q0 << facing_y.w(), facing_y.x(), facing_y.y(), facing_y.z(), 0, 0, 0;
  Eigen::MatrixXd q, ground;
  IntegrateVelocities(true, q0, times, u, BaseVelocityFrame::kHeading, q, ground);
  EXPECT_NEAR(q(100, 4), 0.0, 1e-12);
  EXPECT_NEAR(q(100, 5), 1.0, 1e-12);
  EXPECT_NEAR(ground(50, 4), 1.0, 1e-12);
  // Turning at 1 rad/s while walking forward traces a circle of radius 1: the heading follows the turn.
  u.col(2).setOnes();
  Eigen::VectorXd q_start(7);
  q_start << 1, 0, 0, 0, 0, 0, 0;
  IntegrateVelocities(true, q_start, Eigen::VectorXd::LinSpaced(1001, 0.0, M_PI), Eigen::MatrixXd(u.row(0).replicate(1001, 1)),
                      BaseVelocityFrame::kHeading, q, ground);
  EXPECT_NEAR(q(1000, 4), 0.0, 1e-5);  // half a circle: back on the Y axis at y = 2
  EXPECT_NEAR(q(1000, 5), 2.0, 1e-5);
}

}  // namespace
}  // namespace syn
