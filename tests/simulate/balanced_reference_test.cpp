// The ground mode's balance plan on a real retargeted CMU walk: the zero-moment point it plans, computed
// here from the plan's own centre-of-mass motion and momentum by moment balance, lies inside the support
// polygon it names (the retargeted motion's own lies outside in most frames: the plan reports how many it
// corrected); and the polygon geometry it uses against a direct computation.
#include <cmath>
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

}  // namespace
}  // namespace syn
