// The capture's floor plane (stages/retarget/floor_levelling.h) on synthetic walks over known floors: a
// tilted plane is found and levelled, stepping stones and a dance in place are not taken for a tilt, and a
// level floor is left alone.
#include <gtest/gtest.h>

#include <cmath>
#include <vector>

#include <Eigen/Geometry>

#include "stages/retarget/floor_levelling.h"

namespace syn {
namespace {

constexpr double kRate = 120.0;

struct Walk {
  std::vector<double> time;
  std::vector<std::vector<Eigen::Vector3d>> feet;  // [foot][frame] ankle positions
  std::vector<std::vector<bool>> stance;           // [foot][frame]: flat on the floor
};

// Two ankles walking `steps` strides of `stride` m along x at 0.6 s per step, 8 cm above the floor
// z = floor(x, y) while flat; each heel rises 3 cm over the last 0.1 s of a stance (slow and high, as a
// real heel-off); swings lift 15 cm. `stance_lift(foot, step)` raises a stance by that much (stepping
// stones). 1 mm of deterministic noise.
template <typename Floor, typename Lift>
Walk MakeWalk(const Floor& floor, const Lift& stance_lift, int steps, double stride) {
  Walk walk;
  walk.feet.resize(2);
  walk.stance.resize(2);
  const double step_time = 0.6;
  const int frames = static_cast<int>((steps + 1) * step_time * kRate);
  for (int k = 0; k < frames; ++k) {
    const double t = k / kRate;
    walk.time.push_back(t);
    for (int f = 0; f < 2; ++f) {
      // Foot f swings during odd/even steps; its stance position is that of its last landing.
      const double phase = t / step_time - f;  // steps since this foot's first swing started
      const int step = static_cast<int>(std::floor(std::max(phase, 0.0)));
      const bool swinging = phase >= 0 && (step % 2 == 0) && step < steps;
      const double landed = stride * std::ceil(std::max(phase, 0.0) / 2.0);
      double x = landed, lift = 0;
      if (swinging) {
        const double s = phase - step;  // 0..1 within the swing
        x = stride * (step / 2) + stride * s;
        lift = 0.15 * std::sin(M_PI * s);
      }
      const double y = f == 0 ? 0.1 : -0.1;
      const int stone = static_cast<int>(std::round(x / stride));
      double z = floor(x, y) + 0.08 + stance_lift(f, stone) + lift;
      if (!swinging) {
        // Heel-off: the ankle rises in the 0.1 s before this foot's next swing.
        const double next_swing = step_time * (f + 2 * std::ceil(std::max(phase, 0.0) / 2.0));
        const double before = next_swing - t;
        if (before < 0.1 && before > 0 && step < steps) z += 0.03 * (1 - before / 0.1);
      }
      walk.feet[static_cast<size_t>(f)].emplace_back(x + 0.001 * std::sin(37.0 * k + f), y + 0.001 * std::cos(53.0 * k),
                                                     z + 0.001 * std::sin(71.0 * k + 3 * f));
      walk.stance[static_cast<size_t>(f)].push_back(!swinging);
    }
  }
  return walk;
}

// The walk's ankles as landmarks "left_foot" and "right_foot", with identity orientations.
LandmarkTrajectories AsLandmarks(const Walk& walk) {
  LandmarkTrajectories landmarks;
  landmarks.names = {"left_foot", "right_foot"};
  landmarks.has_orientation = {true, true};
  landmarks.frames = static_cast<int64_t>(walk.time.size());
  for (size_t t = 0; t < walk.time.size(); ++t) {
    for (int f = 0; f < 2; ++f) {
      const Eigen::Vector3d& p = walk.feet[static_cast<size_t>(f)][t];
      landmarks.pose.insert(landmarks.pose.end(), {p.x(), p.y(), p.z(), 1.0, 0.0, 0.0, 0.0});
    }
  }
  return landmarks;
}

// Standard deviation of the flat-stance ankle heights in `landmarks` (heel-offs left out).
double StanceHeightSpread(const Walk& walk, const LandmarkTrajectories& landmarks) {
  std::vector<double> heights;
  for (size_t t = 0; t + 1 < walk.time.size(); ++t) {
    for (int f = 0; f < 2; ++f) {
      const bool still = walk.stance[static_cast<size_t>(f)][t] &&
                         std::abs(walk.feet[static_cast<size_t>(f)][t + 1].z() - walk.feet[static_cast<size_t>(f)][t].z()) < 1e-2 / kRate;
      if (still) heights.push_back(landmarks.pose[(t * 2 + static_cast<size_t>(f)) * 7 + 2]);
    }
  }
  double mean = 0, squares = 0;
  for (double h : heights) mean += h / static_cast<double>(heights.size());
  for (double h : heights) squares += (h - mean) * (h - mean);
  return std::sqrt(squares / static_cast<double>(heights.size()));
}

const auto kNoLift = [](int, int) { return 0.0; };

TEST(FloorLevelling, ATiltedFloorIsFoundAndLevelled) {
  // CMU 08_04's floor: rising 18.7 mm/m along the walk and 14 mm/m across it. Across, the two feet
  // 0.2 m apart are all the spread there is (under min_spread): a real capture's left and right ankle
  // landmarks differ in height by millimetres of marker placement, which would read as a lateral tilt of
  // degrees, so only the tilt along the walk is fitted.
  const double ax = 0.0187, ay = 0.014;
  const Walk walk = MakeWalk([&](double x, double y) { return 0.3 + ax * x + ay * y; }, kNoLift, 8, 0.6);
  const FloorPlane plane = EstimateFloorPlane(walk.feet, walk.time, {});
  const double truth = std::atan(ax);
  EXPECT_TRUE(plane.levelled) << plane.note;
  EXPECT_NEAR(plane.tilt_rad, truth, 0.05 * M_PI / 180) << "tilt " << plane.tilt_rad * 180 / M_PI << "°";
  EXPECT_NEAR(plane.normal.x(), -ax / std::sqrt(1 + ax * ax + ay * ay), 0.002);
  EXPECT_LT(plane.residual, 0.003);
  EXPECT_GT(plane.kept_fraction, 0.8);  // all but the heels rising
  LandmarkTrajectories landmarks = AsLandmarks(walk);
  const double before = StanceHeightSpread(walk, landmarks);
  LevelLandmarks(plane, landmarks);
  const double after = StanceHeightSpread(walk, landmarks);
  EXPECT_GT(before, 0.01);   // 5 cm of rise over the walk
  EXPECT_LT(after, 0.003);   // the noise and the feet's 2.8 mm lateral difference
  // Orientations turn with the positions, about a horizontal axis: the heading stays.
  const Eigen::Quaterniond turned(landmarks.pose[3], landmarks.pose[4], landmarks.pose[5], landmarks.pose[6]);
  EXPECT_NEAR((turned * plane.normal - Eigen::Vector3d::UnitZ()).norm(), 0.0, 1e-12);
  EXPECT_NEAR(turned.toRotationMatrix()(1, 0) - turned.toRotationMatrix()(0, 1), 0.0, 1e-6);
}

TEST(FloorLevelling, SteppingStonesAreNotATiltedFloor) {
  // Stones 0-12 cm high in no order (CMU 03's walks over uneven terrain scatter 26-53 mm about any plane):
  // whatever plane the stance samples fit, the take is not turned by it.
  const double heights[] = {0.0, 0.08, 0.03, 0.12, 0.05, 0.10, 0.01, 0.07, 0.11, 0.02};
  const Walk walk = MakeWalk([](double, double) { return 0.0; }, [&](int, int stone) { return heights[stone % 10]; }, 8, 0.6);
  const FloorPlane plane = EstimateFloorPlane(walk.feet, walk.time, {});
  EXPECT_FALSE(plane.levelled) << "tilt " << plane.tilt_rad * 180 / M_PI << "°, residual " << plane.residual;
  EXPECT_LT(plane.kept_fraction, 0.5);
  EXPECT_NE(plane.note.find("not levelled"), std::string::npos) << plane.note;
}

TEST(FloorLevelling, AMotionInPlaceGivesNoSlope) {
  // Steps of 5 cm on a floor tilted 2°: the feet spread too little along x to see it (nor along y, 0.1 m
  // apart), so no slope is fitted and nothing is turned.
  const Walk walk = MakeWalk([](double x, double y) { return std::tan(2 * M_PI / 180) * (x + y); }, kNoLift, 6, 0.05);
  const FloorPlane plane = EstimateFloorPlane(walk.feet, walk.time, {});
  EXPECT_FALSE(plane.levelled);
  EXPECT_EQ(plane.tilt_rad, 0.0);
}

TEST(FloorLevelling, ALevelFloorIsLeftAlone) {
  // 0.1°: within what a level floor's fit gives (min_tilt 0.29°).
  const Walk walk = MakeWalk([](double x, double) { return std::tan(0.1 * M_PI / 180) * x; }, kNoLift, 8, 0.6);
  const FloorPlane plane = EstimateFloorPlane(walk.feet, walk.time, {});
  EXPECT_NEAR(plane.tilt_rad, 0.1 * M_PI / 180, 0.05 * M_PI / 180);
  EXPECT_FALSE(plane.levelled);
  LandmarkTrajectories landmarks = AsLandmarks(walk);
  const std::vector<double> before = landmarks.pose;
  LevelLandmarks(plane, landmarks);
  EXPECT_EQ(landmarks.pose, before);
  // Switched off, a tilted floor is measured and not turned.
  FloorLevellingOptions off;
  off.enabled = false;
  const Walk tilted = MakeWalk([](double x, double) { return 0.02 * x; }, kNoLift, 8, 0.6);
  const FloorPlane measured = EstimateFloorPlane(tilted.feet, tilted.time, off);
  EXPECT_FALSE(measured.levelled);
  EXPECT_NEAR(measured.tilt_rad, std::atan(0.02), 0.05 * M_PI / 180);
}

}  // namespace
}  // namespace syn
