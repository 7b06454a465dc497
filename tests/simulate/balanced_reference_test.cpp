// The ground mode's balance plan on a real retargeted CMU walk: the zero-moment point it plans, computed
// here from the plan's own centre-of-mass motion and momentum by moment balance, lies inside the support
// polygon it names (the retargeted motion's own lies outside in most frames: the plan reports how many it
// corrected); and the polygon geometry it uses against a direct computation.
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <random>

#include <gtest/gtest.h>

#include "common/model.h"
#include "common/robot_map.h"
#include "stages/simulate/balanced_reference.h"
#include "tests/support/demo_motion.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

using testing::SourcePath;

bool Inside(const Eigen::Vector2d& p, const std::vector<Eigen::Vector2d>& hull, double tolerance) {
  return (ClosestInPolygon(p, hull) - p).norm() <= tolerance;
}

// An axis-aligned box: its hull is its four corners, and the nearest point of it is the clamp.
TEST(BalancePlan, PolygonGeometryMatchesABox) {
  std::mt19937 random(5);
  std::uniform_real_distribution<double> inside_x(-0.05, 0.12), inside_y(-0.03, 0.03), anywhere(-0.5, 0.5);
  std::vector<Eigen::Vector2d> points = {{-0.05, -0.03}, {0.12, -0.03}, {0.12, 0.03}, {-0.05, 0.03}};
  for (int i = 0; i < 40; ++i) points.emplace_back(inside_x(random), inside_y(random));
  std::vector<Eigen::Vector2d> hull;
  ConvexHull(points, hull);
  ASSERT_EQ(hull.size(), 4u);
  for (int i = 0; i < 1000; ++i) {
    const Eigen::Vector2d p(anywhere(random), anywhere(random));
    const Eigen::Vector2d clamped(std::clamp(p.x(), -0.05, 0.12), std::clamp(p.y(), -0.03, 0.03));
    EXPECT_LT((ClosestInPolygon(p, hull) - clamped).norm(), 1e-12) << p.transpose();
  }
  // A segment (a foot on its toe edge) and a point (one corner).
  const std::vector<Eigen::Vector2d> segment = {{0.0, -0.03}, {0.0, 0.03}}, corner = {{0.1, 0.2}};
  EXPECT_LT((ClosestInPolygon({0.2, 0.01}, segment) - Eigen::Vector2d(0.0, 0.01)).norm(), 1e-12);
  EXPECT_LT((ClosestInPolygon({0.2, 0.5}, segment) - Eigen::Vector2d(0.0, 0.03)).norm(), 1e-12);
  EXPECT_LT((ClosestInPolygon({-1.0, 0.5}, corner) - corner[0]).norm(), 1e-12);
}

TEST(BalancePlan, PlannedZmpStaysInsideTheFeetOnARealWalk) {
  const Model model = Model::Load(SourcePath(testing::kG1Urdf));
  const RobotMap map = LoadRobotMap(SourcePath(testing::kG1Map));
  const MotionData& walk = testing::DemoMotionOnG1("02_01");
  const BalanceOptions options;
  const BalanceShift plan = PlanBalanceShift(walk, model, map, options);
  const size_t frames = walk.time_s.size();
  ASSERT_EQ(plan.zmp.size(), frames);
  const double mass = model.totalMass(), gravity = model.gravity();
  int checked = 0, inside = 0, consistent = 0;
  for (size_t t = 0; t < frames; ++t) {
    // Every frame, the first ones too: the plan is free at its start (held at rest for its first two
    // frames, as it was, its zero-moment point lay 4-7 cm outside the left sole through the first left
    // stance, and this test skipped the first 0.6 s).
    if (plan.support[t].empty()) continue;
    const double vertical = mass * (gravity + plan.com_height_acceleration[t]);
    if (vertical < 0.3 * mass * gravity) continue;  // where the plan caps the pendulum's time constant
    // Moment balance about the floor point p: (c − p) × F + L̇ has no horizontal part, F = m (c̈ + g).
    const Eigen::Vector2d& c = plan.com[t];
    const double height = plan.com_height[t];
    const Eigen::Vector3d& rate = plan.angular_momentum_rate[t];
    const Eigen::Vector2d zmp(c.x() - (height * mass * plan.com_acceleration[t].x() + rate.y()) / vertical,
                              c.y() - (height * mass * plan.com_acceleration[t].y() - rate.x()) / vertical);
    ++checked;
    consistent += (zmp - plan.zmp[t]).norm() < 2e-3 ? 1 : 0;
    // The support is the soles' polygon shrunk by the margin: within the margin of it is on the soles.
    inside += Inside(zmp, plan.support[t], options.margin) ? 1 : 0;
  }
  ASSERT_GT(checked, static_cast<int>(frames) * 3 / 4);
  EXPECT_GE(consistent, 0.95 * checked) << consistent << " of " << checked;
  EXPECT_GE(inside, 0.95 * checked) << inside << " of " << checked;
  EXPECT_GT(plan.corrected_frames, static_cast<int64_t>(frames) / 4);
  std::cout << "02_01 on G1: planned zmp inside the support in " << inside << " of " << checked
            << " frames; largest shift " << plan.largest_shift * 1000 << " mm; the reference's zmp corrected in "
            << plan.corrected_frames << " of " << frames << " frames, by up to " << plan.largest_zmp_correction * 1000
            << " mm\n";
}

// In a turn the plan's support is the standing soles' centre lines (BalanceOptions::centre_line_turn): on
// CMU 09_12, which turns on the spot, the frames where the reference's base heading ranges over more than
// 30 deg within half a second either side (measured here by the test's own formula on the free joint's
// quaternion, not common/'s BaseYaw the plan uses) have a support polygon of less area than the soles' whole width gives, a bare segment where one
// foot stands; every other frame has the same polygon either way.
double Area(const std::vector<Eigen::Vector2d>& hull) {
  double twice = 0;
  for (size_t i = 0; i < hull.size(); ++i) {
    const Eigen::Vector2d& a = hull[i];
    const Eigen::Vector2d& b = hull[(i + 1) % hull.size()];
    twice += a.x() * b.y() - a.y() * b.x();
  }
  return 0.5 * std::abs(twice);
}

TEST(BalancePlan, InATurnTheSupportIsTheSolesCentreLines) {
  SYN_REQUIRE_SHARED("cmu_bvh/09/09_12.bvh");
  const Model model = Model::Load(SourcePath(testing::kG1Urdf));
  const RobotMap map = LoadRobotMap(SourcePath(testing::kG1Map));
  const MotionData walk = testing::CmuBvhOnG1(testing::SharedPath("cmu_bvh/09/09_12.bvh"));
  BalanceOptions wide_options;
  wide_options.centre_line_turn = 1e6;
  const BalanceShift plan = PlanBalanceShift(walk, model, map, BalanceOptions{});
  const BalanceShift wide = PlanBalanceShift(walk, model, map, wide_options);
  const size_t frames = walk.time_s.size(), nq = static_cast<size_t>(walk.nq());
  std::vector<double> heading(frames);
  for (size_t t = 0; t < frames; ++t) {
    const double* q = &walk.q[t * nq];  // the free joint's quaternion (w, x, y, z) first
    heading[t] = std::atan2(2 * (q[0] * q[3] + q[1] * q[2]), 1 - 2 * (q[2] * q[2] + q[3] * q[3]));
    while (t > 0 && heading[t] - heading[t - 1] > M_PI) heading[t] -= 2 * M_PI;
    while (t > 0 && heading[t] - heading[t - 1] < -M_PI) heading[t] += 2 * M_PI;
  }
  int turning = 0, narrower = 0, segments = 0, straight = 0;
  for (size_t t = 0; t < frames; ++t) {
    double low = heading[t], high = heading[t];
    for (size_t k = 0; k < frames; ++k) {
      if (std::abs(walk.time_s[k] - walk.time_s[t]) <= 0.5) low = std::min(low, heading[k]), high = std::max(high, heading[k]);
    }
    const double turn = (high - low) * 180 / M_PI;
    if (turn < 29) {
      ++straight;
      ASSERT_EQ(plan.support[t].size(), wide.support[t].size()) << "frame " << t;
      for (size_t v = 0; v < plan.support[t].size(); ++v) EXPECT_EQ(plan.support[t][v], wide.support[t][v]) << "frame " << t;
    } else if (turn > 31 && Area(wide.support[t]) > 1e-4) {
      ++turning;
      if (Area(plan.support[t]) < Area(wide.support[t]) - 1e-6) ++narrower;
      if (plan.support[t].size() <= 2 && wide.support[t].size() >= 3) ++segments;
    }
  }
  std::printf("09_12: %d frames turning over 30 deg with a sole flat on the floor, %d of them with a narrower support, "
              "%d a bare segment; %d straight frames alike\n", turning, narrower, segments, straight);
  EXPECT_GT(turning, 60) << "09_12 turns on the spot for over half a second";
  EXPECT_GE(narrower, turning * 9 / 10);
  EXPECT_GT(segments, 0);
  EXPECT_GT(straight, 0);
}

}  // namespace
}  // namespace syn
