// Source foot contacts (stages/retarget/contact_detection.h) on a synthetic gait with known stance
// phases, and on a real CMU walk whose two feet must alternate.
#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <limits>
#include <string>
#include <vector>

#include "common/markers_file.h"
#include "stages/ingest/ingest.h"
#include "stages/retarget/contact_detection.h"
#include "stages/retarget/landmarks.h"
#include "common/marker_set.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

constexpr double kRate = 120.0;

// A foot that is planted (ankle 8 cm above a floor at z = -0.3, still) in [start, end) s of each
// planted interval and swings otherwise (rising 15 cm, moving forward at 1.5 m/s).
std::vector<Eigen::Vector3d> SyntheticFoot(const std::vector<std::pair<double, double>>& planted, double duration,
                                           std::vector<uint8_t>* truth) {
  std::vector<Eigen::Vector3d> foot;
  double x = 0;
  for (int k = 0; k < static_cast<int>(duration * kRate); ++k) {
    const double t = k / kRate;
    bool down = false;
    double swing_start = 0, swing_end = duration;
    for (size_t i = 0; i < planted.size(); ++i) {
      if (t >= planted[i].first && t < planted[i].second) down = true;
      if (planted[i].second <= t) swing_start = planted[i].second;
      if (planted[i].first > t && planted[i].first < swing_end) swing_end = planted[i].first;
    }
    double z = -0.3 + 0.08;
    if (!down) {
      x += 1.5 / kRate;
      z += 0.15 * std::sin(M_PI * (t - swing_start) / (swing_end - swing_start));
    }
    // 1 mm of deterministic sensor noise.
    foot.emplace_back(x + 0.001 * std::sin(37.0 * k), 0.1 + 0.001 * std::cos(53.0 * k), z + 0.001 * std::sin(71.0 * k));
    truth->push_back(down);
  }
  return foot;
}

// The left and right foot landmarks of a shared CMU BVH take (`bvh` under cmu_bvh/), ingested as the
// stage does; `capture` gets the ingested take. Empty, with a failure recorded, if a foot landmark is missing.
std::vector<std::vector<Eigen::Vector3d>> CmuFootLandmarks(const std::string& bvh, const std::string& take, MarkerData& capture) {
  IngestOptions ingest;
  ingest.drop_first_frame = true;
  capture = IngestCapture(testing::SharedPath("cmu_bvh/" + bvh), ingest, nullptr);
  const LandmarkTrajectories landmarks =
      ComputeLandmarks(capture, LoadMarkerSet(testing::SourcePath("manifests/markersets/cmu-bvh.toml")), take);
  std::vector<std::vector<Eigen::Vector3d>> feet(2);
  for (int f = 0; f < 2; ++f) {
    const auto found = std::find(landmarks.names.begin(), landmarks.names.end(), f == 0 ? "left_foot" : "right_foot");
    if (found == landmarks.names.end()) {
      ADD_FAILURE() << take << ": no " << (f == 0 ? "left_foot" : "right_foot") << " landmark";
      return {};
    }
    const int64_t l = found - landmarks.names.begin();
    for (int64_t t = 0; t < landmarks.frames; ++t) {
      const double* pose = &landmarks.pose[static_cast<size_t>((t * landmarks.count() + l) * 7)];
      feet[static_cast<size_t>(f)].emplace_back(pose[0], pose[1], pose[2]);
    }
  }
  return feet;
}

int PhasesOf(const FootContacts& contacts, int foot) {
  int phases = 0;
  for (const ContactPhase& phase : contacts.phases) phases += phase.foot == foot;
  return phases;
}

// A walk's two feet: each planted in min_phases..max_phases phases and for 30-75 % of the frames (stance is
// about 60 % of a human gait cycle).
void ExpectWalkingStances(const FootContacts& contacts, int min_phases, int max_phases) {
  for (int f = 0; f < 2; ++f) {
    const int phases = PhasesOf(contacts, f);
    EXPECT_GE(phases, min_phases) << "foot " << f;
    EXPECT_LE(phases, max_phases) << "foot " << f;
    const double fraction = static_cast<double>(contacts.framesInContact(f)) / static_cast<double>(contacts.frames);
    EXPECT_GT(fraction, 0.3) << "foot " << f;
    EXPECT_LT(fraction, 0.75) << "foot " << f;
  }
}

// s: the longest run of frames with neither of two feet planted (walking has no flight phase).
double LongestGapWithNoFootPlanted(const FootContacts& contacts, double rate_hz) {
  int64_t airborne = 0, longest = 0;
  for (int64_t t = 0; t < contacts.frames; ++t) {
    airborne = contacts.at(t, 0) || contacts.at(t, 1) ? 0 : airborne + 1;
    longest = std::max(longest, airborne);
  }
  return static_cast<double>(longest) / rate_hz;
}

TEST(ContactDetection, FindsTheStancePhasesOfASyntheticGait) {
  const double duration = 3.0;
  std::vector<uint8_t> left_truth, right_truth;
  // The right foot's 0.05 s touch is shorter than the minimum duration: not a contact.
  const std::vector<std::vector<Eigen::Vector3d>> feet = {
      SyntheticFoot({{0.0, 0.6}, {1.0, 1.6}, {2.0, 2.6}}, duration, &left_truth),
      SyntheticFoot({{0.4, 1.1}, {1.5, 1.55}, {1.9, 2.7}}, duration, &right_truth)};
  std::vector<double> time;
  for (size_t k = 0; k < feet[0].size(); ++k) time.push_back(static_cast<double>(k) / kRate);
  const FootContacts contacts = DetectContacts(feet, time, {});
  EXPECT_NEAR(contacts.ground, -0.3 + 0.08, 0.002);
  ASSERT_EQ(contacts.phases.size(), 5u);
  for (int f = 0; f < 2; ++f) {
    const std::vector<uint8_t>& truth = f == 0 ? left_truth : right_truth;
    int disagreements = 0;
    for (int64_t t = 0; t < contacts.frames; ++t) {
      const bool expected = truth[static_cast<size_t>(t)] && !(f == 1 && time[static_cast<size_t>(t)] >= 1.5 && time[static_cast<size_t>(t)] < 1.55);
      if (contacts.at(t, f) != expected) ++disagreements;
    }
    // The speed window (0.05 s) blurs each edge by a few frames; nothing else may differ.
    EXPECT_LE(disagreements, 6 * 4) << "foot " << f;
  }
}

TEST(ContactDetection, APhaseTheRecordingCutsIsKeptHoweverShort) {
  // The left foot is planted for the recording's first 0.05 s and its last 0.04 s, the right for 0.05 s
  // in between: all three shorter than the 0.1 s minimum, only the middle one dropped.
  const double duration = 2.0;
  std::vector<uint8_t> left_truth, right_truth;
  const std::vector<std::vector<Eigen::Vector3d>> feet = {
      SyntheticFoot({{0.0, 0.05}, {1.96, 2.0}}, duration, &left_truth),
      SyntheticFoot({{0.5, 0.55}, {1.2, 1.9}}, duration, &right_truth)};
  std::vector<double> time;
  for (size_t k = 0; k < feet[0].size(); ++k) time.push_back(static_cast<double>(k) / kRate);
  const FootContacts contacts = DetectContacts(feet, time, {});
  ASSERT_EQ(contacts.phases.size(), 3u);
  EXPECT_EQ(contacts.phases[0].foot, 0);
  EXPECT_EQ(contacts.phases[0].begin, 0);
  EXPECT_GE(contacts.phases[0].end, 4);  // 6 planted frames, the speed window blurring the lift-off
  EXPECT_EQ(contacts.phases[1].foot, 0);
  EXPECT_EQ(contacts.phases[1].end, contacts.frames);
  EXPECT_EQ(contacts.phases[2].foot, 1);
  EXPECT_GT(time[static_cast<size_t>(contacts.phases[2].begin)], 1.1);
}

TEST(ContactDetection, HysteresisKeepsAContactThroughNoiseAtTheThreshold) {
  // A planted foot creeping at 0.4 m/s (between the begin speed 0.33 and the end speed 0.5): once
  // planted at rest, it stays planted; a foot that only ever creeps at 0.4 m/s never begins one.
  std::vector<double> time;
  std::vector<Eigen::Vector3d> resting_then_creeping, creeping;
  for (int k = 0; k < 240; ++k) {
    const double t = k / kRate;
    time.push_back(t);
    resting_then_creeping.emplace_back(t < 0.5 ? 0.0 : 0.4 * (t - 0.5), 0, 0.08);
    creeping.emplace_back(0.4 * t, 0, 0.08);
  }
  const FootContacts contacts = DetectContacts({resting_then_creeping, creeping}, time, {});
  EXPECT_EQ(contacts.framesInContact(0), 240);
  EXPECT_EQ(contacts.framesInContact(1), 0);
}

TEST(ContactDetection, CmuWalkAlternatesItsFeet) {
  SYN_REQUIRE_SHARED("cmu_bvh/02/02_01.bvh");
  MarkerData capture;
  const std::vector<std::vector<Eigen::Vector3d>> feet = CmuFootLandmarks("02/02_01.bvh", "02_01", capture);
  ASSERT_EQ(feet.size(), 2u);
  const FootContacts contacts = DetectContacts(feet, capture.time_s, {});
  // 02_01 is 2.9 s of walking, about 2.5 strides: each foot is planted 2–4 times, for 30–75 % of the
  // frames (stance is ~60 % of a human gait cycle), and at every frame at least one foot is down or
  // the walk is in a swing of at most 0.15 s (walking has no flight phase; detection edges blur it).
  ExpectWalkingStances(contacts, 2, 4);
  // The capture begins with the right foot at rest before its heel rises (9 frames): planted, though
  // shorter than the minimum duration, since the recording cut it.
  EXPECT_TRUE(contacts.at(0, 1)) << "the right foot at the first frame";
  EXPECT_LE(LongestGapWithNoFootPlanted(contacts, capture.rate_hz), 0.15);
}

// Uneven ground: a walk whose stances stand at different heights. Each foot alternates `stances` (begin,
// end, height of the ankle above the floor) with swings that move it forward at 1.5 m/s and lift it 15 cm
// above the higher of the stances around it.
std::vector<Eigen::Vector3d> SteppingFoot(const std::vector<std::array<double, 3>>& stances, double duration) {
  std::vector<Eigen::Vector3d> foot;
  double x = 0;
  for (int k = 0; k < static_cast<int>(duration * kRate); ++k) {
    const double t = k / kRate;
    const std::array<double, 3>* before = nullptr;
    const std::array<double, 3>* after = nullptr;
    const std::array<double, 3>* on = nullptr;
    for (const std::array<double, 3>& stance : stances) {
      if (t >= stance[0] && t < stance[1]) on = &stance;
      if (stance[1] <= t) before = &stance;
      if (stance[0] > t && after == nullptr) after = &stance;
    }
    double z = 0;
    if (on != nullptr) {
      z = (*on)[2];
    } else {
      const double from = before ? (*before)[1] : 0.0, to = after ? (*after)[0] : duration;
      const double low = before ? (*before)[2] : 0.0, high = after ? (*after)[2] : low;
      const double s = (t - from) / (to - from);
      x += 1.5 / kRate;
      z = low + (high - low) * s + 0.15 * std::sin(M_PI * s);
    }
    foot.emplace_back(x + 0.001 * std::sin(37.0 * k), 0.1, z + 0.001 * std::sin(71.0 * k));
  }
  return foot;
}

bool PlantedThrough(const FootContacts& contacts, const std::vector<double>& time, int foot, double from, double to) {
  for (int64_t t = 0; t < contacts.frames; ++t) {
    const double now = time[static_cast<size_t>(t)];
    if (now >= from && now < to && !contacts.at(t, foot)) return false;
  }
  return true;
}

TEST(ContactDetection, FindsStancesOnRaisedGround) {
  // Left on the floor (ankle 8 cm up), then on a 20 cm block, then on a 12 cm one; right on a 15 cm block, a
  // 25 cm one and the floor. With the ground's band alone (5 cm) only the floor stances are contacts.
  const double duration = 3.0;
  const std::vector<std::vector<Eigen::Vector3d>> feet = {
      SteppingFoot({{{0.0, 0.6, 0.08}}, {{1.0, 1.6, 0.28}}, {{2.0, 2.6, 0.20}}}, duration),
      SteppingFoot({{{0.5, 1.1, 0.23}}, {{1.5, 2.1, 0.33}}, {{2.5, 3.0, 0.08}}}, duration)};
  std::vector<double> time;
  for (size_t k = 0; k < feet[0].size(); ++k) time.push_back(static_cast<double>(k) / kRate);
  ContactDetectionOptions flat;
  flat.uneven_ground = false;
  const FootContacts on_the_floor = DetectContacts(feet, time, flat);
  EXPECT_EQ(on_the_floor.phases.size(), 2u);
  const FootContacts contacts = DetectContacts(feet, time, {});
  ASSERT_EQ(contacts.phases.size(), 6u);
  // A raised stance begins once the other foot swings above it (the left leaving the floor for a 20 cm
  // block passes the right's 15 cm block at about 0.72 s) and lasts until the foot itself swings.
  EXPECT_TRUE(PlantedThrough(contacts, time, 0, 1.15, 1.45));  // left on 20 cm while the right swings
  EXPECT_TRUE(PlantedThrough(contacts, time, 0, 2.15, 2.45));
  EXPECT_TRUE(PlantedThrough(contacts, time, 1, 0.76, 0.95));  // right on 15 cm
  EXPECT_TRUE(PlantedThrough(contacts, time, 1, 1.7, 1.95));  // right on 25 cm, the left passing above at 1.67 s
  for (const ContactPhase& phase : contacts.phases) {
    EXPECT_GE(time[static_cast<size_t>(phase.end - 1)] - time[static_cast<size_t>(phase.begin)], 0.25)
        << "foot " << phase.foot << " from frame " << phase.begin;
  }
  // Swinging frames are never planted.
  for (int64_t t = 0; t < contacts.frames; ++t) {
    const double now = time[static_cast<size_t>(t)];
    if (now > 0.65 && now < 0.95) {
      EXPECT_FALSE(contacts.at(t, 0)) << "left swings at " << now << " s";
    }
    if (now > 1.15 && now < 1.45) {
      EXPECT_FALSE(contacts.at(t, 1)) << "right swings at " << now << " s";
    }
  }
}

TEST(ContactDetection, AFootHeldStillInTheAirIsNotPlanted) {
  // A dancer on one leg: the right foot planted on the floor, the left held still 30 cm up; then the left
  // turning on its ball (ankle 7 cm up) while the right jitters fast in place without stepping anywhere.
  std::vector<double> time;
  std::vector<Eigen::Vector3d> left, right;
  for (int k = 0; k < 360; ++k) {
    const double t = k / kRate;
    time.push_back(t);
    const bool turning = t >= 1.5;
    left.emplace_back(0.0, 0.1, turning ? 0.15 : 0.38);
    right.emplace_back(turning ? 0.03 * std::sin(40.0 * t) : 0.0, -0.1, turning ? 0.25 + 0.03 * std::sin(40.0 * t) : 0.08);
  }
  const FootContacts contacts = DetectContacts({left, right}, time, {});
  EXPECT_EQ(contacts.framesInContact(0), 0);
}

TEST(ContactDetection, CmuTerrainWalkAlternatesItsFeet) {
  // CMU 03_01 walks over uneven terrain: its stances stand up to 20 cm above its floor. With the ground's
  // band alone each foot had one phase (the left at 1.4-2.25 s, the right in its last 0.05 s) in 3.6 s.
  SYN_REQUIRE_SHARED("cmu_bvh/03/03_01.bvh");
  MarkerData capture;
  const std::vector<std::vector<Eigen::Vector3d>> feet = CmuFootLandmarks("03/03_01.bvh", "03_01", capture);
  ASSERT_EQ(feet.size(), 2u);
  const FootContacts contacts = DetectContacts(feet, capture.time_s, {});
  ExpectWalkingStances(contacts, 3, std::numeric_limits<int>::max());
  // Walking has no flight: at most a short gap (detection edges) with neither foot planted, after the
  // first step.
  EXPECT_LE(LongestGapWithNoFootPlanted(contacts, capture.rate_hz), 0.25);
  ContactDetectionOptions flat;
  flat.uneven_ground = false;
  const FootContacts floor_only = DetectContacts(feet, capture.time_s, flat);
  EXPECT_LT(floor_only.framesInContact(0) + floor_only.framesInContact(1),
            (contacts.framesInContact(0) + contacts.framesInContact(1)) / 2);
}

}  // namespace
}  // namespace syn
