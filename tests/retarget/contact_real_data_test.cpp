// What syn-retarget reports about feet and floor is what a forward kinematics independent of the stage
// (tests/support/independent_fk.h, from the URDF text) measures on its output: per trial the share of
// frames with a sole point more than 1 cm below the floor, the deepest point, the stance drift during the
// source's contact phases, and GMD's foot-skating ratio of the robot and of the source's foot targets
// (with the robot's soles). On the demo walk and on every shared CMU walk and dance, onto the G1 and the
// HRP-4C. These are the figures issue 17 must bring down; the tests hold the stage to reporting them
// truthfully, not to their values.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <unistd.h>
#include <vector>

#include <tinyxml2.h>

#include "common/file_bytes.h"
#include "common/intermediate_file.h"
#include "common/markers_file.h"
#include "common/robot_map.h"
#include "common/foot_sliding.h"
#include "stages/ingest/ingest.h"
#include "stages/retarget/retarget.h"
#include "tests/support/demo_motion.h"
#include "tests/support/cmu_index.h"
#include "tests/support/independent_fk.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

double Quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  return values[std::min(values.size() - 1, static_cast<size_t>(q * static_cast<double>(values.size() - 1) + 0.5))];
}

// The column of landmark `name` in the motion's landmark arrays (landmark_names.size() where it has none).
size_t LandmarkColumn(const MotionData& motion, const std::string& name) {
  return static_cast<size_t>(std::find(motion.landmark_names.begin(), motion.landmark_names.end(), name) -
                             motion.landmark_names.begin());
}

// Landmark `column`'s target position at frame t.
Eigen::Vector3d TargetPosition(const MotionData& motion, int64_t t, size_t column) {
  const double* target = &motion.landmark_targets[(static_cast<size_t>(t) * motion.landmark_names.size() + column) * 7];
  return {target[0], target[1], target[2]};
}

struct Robot {
  std::string name, urdf, map;
  std::string pelvis_link;  // the map's pelvis task link
  std::vector<std::string> foot_links;
  std::vector<std::vector<Eigen::Vector3d>> sole_points;  // per foot, link frame (from the robot map text)
};

Robot G1() {
  const std::vector<Eigen::Vector3d> sole = {{-0.05, 0.025, -0.035}, {-0.05, -0.025, -0.035}, {0.12, 0.03, -0.035}, {0.12, -0.03, -0.035}};
  return {"G1", testing::SourcePath(testing::kG1Urdf), testing::SourcePath(testing::kG1Map), "pelvis",
          {"left_ankle_roll_link", "right_ankle_roll_link"}, {sole, sole}};
}

Robot Hrp4c() {
  const std::vector<Eigen::Vector3d> sole = {{-0.02, 0.05, -0.08}, {-0.02, -0.05, -0.08}, {0.18, 0.05, -0.08}, {0.18, -0.05, -0.08}};
  return {"HRP-4C", testing::SharedPath("robots/humanoid_synergies/HRP4c_optitrack_model.urdf"),
          testing::SourcePath("manifests/robots/hrp4c.toml"), "hip_base", {"LL_foot", "RL_foot"}, {sole, sole}};
}

struct ContactCheck {
  int64_t frames = 0;
  double penetrating_fraction = 0;  // frames with a sole point > 1 cm below z = 0
  double hovering_fraction = 0;     // frames whose lowest sole point (of every foot) is > 2 cm above z = 0
  double deepest = 0;               // m below z = 0
  std::vector<double> drift;        // per source contact phase, m
  std::vector<double> lift;         // per source contact phase, its planted sole's lowest point's greatest height, m
  double robot_skating = 0, source_skating = 0;
  // Unplanted foot-frames whose lowest sole point hangs more than 1 cm under the source's (levelled, and
  // never under the floor), as a share of all unplanted foot-frames; and the largest frame-to-frame second
  // difference of a foot's lowest sole point (m), which a foot raised frame by frame against its velocity
  // bound saws up.
  double swing_under_source = 0;
  double largest_lowest_second_difference = 0;
  // The pelvis link's origin: its lowest height, and the most it sinks under its target's height (m). Soles
  // alone do not see a robot whose pelvis goes to the floor while its feet stay planted (CMU 94_07 onto G1
  // before its feet's turns were held: pelvis 0.80 m under its target, at z = -0.02).
  double lowest_pelvis = 1e9;
  double pelvis_sinking = -1e9;
};

// A foot's sole points at `pose`: their centre and the lowest one's height.
FootSample SoleAt(const Eigen::Isometry3d& pose, const std::vector<Eigen::Vector3d>& sole_points) {
  FootSample sample;
  sample.lowest_z = 1e9;
  for (const Eigen::Vector3d& point : sole_points) {
    const Eigen::Vector3d world = pose * point;
    sample.x += world.x() / static_cast<double>(sole_points.size());
    sample.y += world.y() / static_cast<double>(sole_points.size());
    sample.lowest_z = std::min(sample.lowest_z, world.z());
  }
  return sample;
}

// Checks a retargeted motion with the independent FK.
ContactCheck CheckContacts(const MotionData& motion, const Robot& robot, const testing::IndependentFk& fk, bool free_base) {
  ContactCheck check;
  const int64_t frames = motion.frames(), nq = motion.nq();
  const size_t feet = robot.foot_links.size();
  check.frames = frames;
  // Sole points per frame and foot.
  std::vector<std::vector<FootSample>> robot_feet(feet), source_feet(feet);
  std::vector<std::vector<Eigen::Vector2d>> centre(feet);
  int64_t penetrating = 0, hovering = 0;
  const size_t pelvis_task = LandmarkColumn(motion, "pelvis");
  for (int64_t t = 0; t < frames; ++t) {
    const auto poses = fk.poses(motion.coordinate_names, &motion.q[static_cast<size_t>(t * nq)], free_base);
    double lowest_frame = 1e9;
    for (size_t f = 0; f < feet; ++f) {
      const FootSample sample = SoleAt(poses.at(robot.foot_links[f]), robot.sole_points[f]);
      lowest_frame = std::min(lowest_frame, sample.lowest_z);
      robot_feet[f].push_back(sample);
      centre[f].emplace_back(sample.x, sample.y);
    }
    const double pelvis = poses.at(robot.pelvis_link).translation().z();
    check.lowest_pelvis = std::min(check.lowest_pelvis, pelvis);
    if (pelvis_task < motion.landmark_names.size()) {
      const double target = TargetPosition(motion, t, pelvis_task).z();
      if (std::isfinite(target)) check.pelvis_sinking = std::max(check.pelvis_sinking, target - pelvis);
    }
    if (lowest_frame < -0.01) ++penetrating;
    if (lowest_frame > 0.02) ++hovering;
    check.deepest = std::max(check.deepest, -lowest_frame);
  }
  check.penetrating_fraction = static_cast<double>(penetrating) / static_cast<double>(frames);
  check.hovering_fraction = static_cast<double>(hovering) / static_cast<double>(frames);
  // Drift: within each contact phase of the source, the largest horizontal distance of the sole centre
  // from where it was when the phase began.
  EXPECT_EQ(motion.contact_feet.size(), feet);
  for (size_t f = 0; f < feet && motion.contact_feet.size() == feet; ++f) {
    int64_t begin = -1;
    double drift = 0, lift = 0;
    for (int64_t t = 0; t <= frames; ++t) {
      const bool planted = t < frames && motion.contact[static_cast<size_t>(t) * feet + f] != 0;
      if (planted && begin < 0) begin = t, drift = 0, lift = 0;
      if (planted) {
        drift = std::max(drift, (centre[f][static_cast<size_t>(t)] - centre[f][static_cast<size_t>(begin)]).norm());
        lift = std::max(lift, robot_feet[f][static_cast<size_t>(t)].lowest_z);
      }
      if (!planted && begin >= 0) check.drift.push_back(drift), check.lift.push_back(lift), begin = -1;
    }
  }
  // The source's feet scaled to the robot, measured like the robot's: the robot's sole points placed at
  // each foot landmark's target pose (position and orientation), heights from the level the source's
  // planted frames sit at (their median lowest sole point).
  const size_t landmarks = motion.landmark_names.size();
  std::vector<double> planted_levels;
  for (size_t f = 0; f < feet; ++f) {
    const std::string name = f == 0 ? "left_foot" : "right_foot";
    const size_t l = LandmarkColumn(motion, name);
    EXPECT_LT(l, landmarks);
    for (int64_t t = 0; t < frames; ++t) {
      const double* target = &motion.landmark_targets[(static_cast<size_t>(t) * landmarks + l) * 7];
      Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
      pose.translation() = Eigen::Vector3d(target[0], target[1], target[2]);
      if (std::isfinite(target[3])) pose.linear() = Eigen::Quaterniond(target[3], target[4], target[5], target[6]).normalized().toRotationMatrix();
      const FootSample sample = SoleAt(pose, robot.sole_points[f]);
      source_feet[f].push_back(sample);
      if (motion.contact_feet.size() == feet && motion.contact[static_cast<size_t>(t) * feet + f] != 0) {
        planted_levels.push_back(sample.lowest_z);
      }
    }
  }
  const double planted_level = Quantile(planted_levels, 0.5);
  for (auto& foot : source_feet) {
    for (FootSample& sample : foot) sample.lowest_z -= planted_level;
  }
  const double dt = (motion.time_s.back() - motion.time_s.front()) / static_cast<double>(frames - 1);
  FootSlidingOptions sliding;
  sliding.penetration = 1e9;  // the skating measure alone (penetration is checked above)
  auto ratio = [&](const std::vector<std::vector<FootSample>>& samples) {
    const std::vector<uint8_t> flags = FindSlidingFrames(samples, dt, sliding);
    return static_cast<double>(std::count(flags.begin(), flags.end(), 1)) / static_cast<double>(flags.size());
  };
  check.robot_skating = ratio(robot_feet);
  check.source_skating = ratio(source_feet);
  int64_t unplanted = 0, under = 0;
  for (size_t f = 0; f < feet && motion.contact_feet.size() == feet; ++f) {
    for (int64_t t = 0; t < frames; ++t) {
      const size_t i = static_cast<size_t>(t);
      if (t >= 2) {
        const double second = robot_feet[f][i].lowest_z - 2 * robot_feet[f][i - 1].lowest_z + robot_feet[f][i - 2].lowest_z;
        check.largest_lowest_second_difference = std::max(check.largest_lowest_second_difference, std::abs(second));
      }
      if (motion.contact[i * feet + f] != 0) continue;
      ++unplanted;
      under += robot_feet[f][i].lowest_z < std::max(0.0, source_feet[f][i].lowest_z) - 0.01;
    }
  }
  check.swing_under_source = unplanted ? static_cast<double>(under) / static_cast<double>(unplanted) : 0.0;
  return check;
}

// Issue 17's floor bound (at most 1 % of frames with a sole point more than 1 cm below it) and drift bounds
// (stance drift median 10 mm, p95 25 mm over the phases) on one trial.
void ExpectWithinFloorAndDriftBounds(const ContactCheck& check) {
  EXPECT_LE(check.penetrating_fraction, 0.01);
  EXPECT_LE(Quantile(check.drift, 0.5), 0.010);
  EXPECT_LE(Quantile(check.drift, 0.95), 0.025);
}

// The stage's own figures (RetargetSummary) against the independent check of its output.
void ExpectSummaryMatches(const RetargetSummary& summary, const ContactCheck& check) {
  EXPECT_NEAR(summary.deepest_penetration, check.deepest, 2e-3);
  EXPECT_NEAR(summary.penetrating_fraction, check.penetrating_fraction, 0.005);
  EXPECT_EQ(summary.contact_phases.size(), check.drift.size());
  if (!check.drift.empty()) {
    EXPECT_NEAR(summary.median_drift, Quantile(check.drift, 0.5), 1e-3);
  }
  EXPECT_NEAR(summary.foot_skating, check.robot_skating, 0.01);
  EXPECT_NEAR(summary.source_foot_skating, check.source_skating, 0.01);
}

std::string WriteMarkers(const MarkerData& data, const std::string& path) {
  IntermediateWriter writer(path, {kMarkersSchema, kMarkersSchemaVersion, "test", {}, nlohmann::json::array()});
  WriteMarkerData(writer, data);
  writer.commit();
  return path;
}

// A shared CMU BVH (a path under cmu_bvh/) written as a markers file at `path`, its T-pose frame dropped
// (syn-ingest --drop-first-frame) unless it is an excerpt, which has none.
std::string CmuMarkers(const std::string& file, const std::string& path) {
  IngestOptions ingest;
  ingest.drop_first_frame = file.find("_excerpt") == std::string::npos;
  return WriteMarkers(IngestCapture(testing::SharedPath("cmu_bvh/" + file), ingest, nullptr), path);
}

// A test's scratch folder, removed however the test ends (an ASSERT returns early).
struct ScratchDir {
  explicit ScratchDir(const std::string& tag)
      : path(std::filesystem::temp_directory_path() / ("syn_" + tag + "_" + std::to_string(::getpid()))) {
    std::filesystem::create_directories(path);
  }
  ~ScratchDir() { std::filesystem::remove_all(path); }
  std::string file(const std::string& name) const { return path + "/" + name; }
  std::string path;
};

// A CMU BVH capture onto `robot`, every other option the stage's default.
RetargetOptions CmuOptions(const Robot& robot) {
  RetargetOptions options;
  options.model = robot.urdf;
  options.robot_map = robot.map;
  options.markerset = testing::SourcePath("manifests/markersets/cmu-bvh.toml");
  return options;
}

// Over every CMU walk and dance: the stance drift of every contact phase (m), and how many trials meet issue
// 17's floor and skating bounds.
struct SweepResult {
  std::vector<double> drift, lift;  // every contact phase's, as ContactCheck's
  int floor_met = 0, skating_met = 0, drift_met = 0;  // trials within each of issue 17's bounds
  // Walks (index.csv's class): those whose floor the stage found a plane (levelled, or level already), and of
  // those the ones with at most 2 % of frames hovering (every sole point > 2 cm above the floor: walking has
  // no flight phase); and the walks whose floor is no plane (uneven terrain).
  int flat_floor_walks = 0, grounded_walks = 0;
  std::vector<std::string> uneven_floor_walks;
  double lowest_pelvis = 1e9, pelvis_sinking = -1e9;  // over every trial, as ContactCheck's
};

// Contact phases whose planted sole rose more than 5 mm off the floor (ContactCheck::lift).
int64_t LiftedPhases(const std::vector<double>& lift) {
  return std::count_if(lift.begin(), lift.end(), [](double l) { return l > 0.005; });
}

SweepResult CheckEveryWalkAndDance(const Robot& robot, bool free_base) {
  const ScratchDir scratch("contacts");
  const testing::IndependentFk fk(robot.urdf);
  std::vector<double> all_drift, all_lift;
  std::fprintf(stderr, "%-10s %-7s %6s %8s %8s %8s %8s %8s %8s\n", "trial", "robot", "frames", "pen>1cm%", "deepest",
               "drift50", "drift95", "skate", "source");
  int trials = 0, floor_met = 0, skating_met = 0, drift_met = 0, flat_floor_walks = 0, grounded_walks = 0;
  std::vector<std::string> uneven_floor_walks;
  double all_penetrating = 0, all_frames = 0, lowest_pelvis = 1e9, pelvis_sinking = -1e9;
  for (const testing::CmuTrial& trial : testing::CmuTrials({"walk", "dance"})) {
    const std::string& file = trial.file;
    SCOPED_TRACE(file + " onto " + robot.name);
    const std::string markers = CmuMarkers(file, scratch.file("capture.markers.h5"));
    RetargetSummary summary;  // contacts enforced, heading from the pelvis: the defaults
    const MotionData motion = RetargetFile(markers, CmuOptions(robot), &summary);
    const ContactCheck check = CheckContacts(motion, robot, fk, free_base);
    ++trials;
    // What the stage reports is what an independent FK measures on its output (the thresholds are
    // printed below, not asserted: they do not hold on every trial yet — see the issue note).
    ExpectSummaryMatches(summary, check);
    // What stays unreachable is reported (issue 17, item 3): a stance the independent FK sees drift past the
    // issue's p95 bound is one the stage counts frames with a planted foot off its plant for (G1 94_07,
    // HRP-4C 03_02 and 05_11: 87, 15 and 36 frames; until 2026-11-27 the count was of capped base
    // lowering only, and said 0 for both HRP-4C trials).
    const double worst_drift = check.drift.empty() ? 0.0 : *std::max_element(check.drift.begin(), check.drift.end());
    if (worst_drift > 0.025) {
      EXPECT_GT(summary.enforcement.unreachable_frames, 0)
          << "a stance drifts " << 1000 * worst_drift << " mm, and no frame is reported out of reach";
    }
    floor_met += check.penetrating_fraction <= 0.01;
    skating_met += check.robot_skating <= check.source_skating + 0.05;
    drift_met += Quantile(check.drift, 0.5) <= 0.010 && Quantile(check.drift, 0.95) <= 0.025;
    const std::string stem = std::filesystem::path(file).stem().string();
    if (trial.motion_class == "walk") {
      // A floor the stage did not level although tilted more than it corrects is no plane (its note says so).
      const bool plane = summary.floor_levelled || summary.floor_tilt_rad < CmuOptions(robot).floor.min_tilt;
      if (plane) {
        ++flat_floor_walks;
        grounded_walks += check.hovering_fraction <= 0.02;
        if (check.hovering_fraction > 0.02) {
          std::fprintf(stderr, "%s onto %s: %.1f %% of frames hovering more than 2 cm above the floor\n", stem.c_str(),
                       robot.name.c_str(), 100 * check.hovering_fraction);
        }
      } else {
        uneven_floor_walks.push_back(stem);
      }
    }
    all_drift.insert(all_drift.end(), check.drift.begin(), check.drift.end());
    all_lift.insert(all_lift.end(), check.lift.begin(), check.lift.end());
    lowest_pelvis = std::min(lowest_pelvis, check.lowest_pelvis);
    pelvis_sinking = std::max(pelvis_sinking, check.pelvis_sinking);
    if (check.pelvis_sinking > 0.3) {
      std::fprintf(stderr, "%s onto %s: pelvis %.0f mm under its target at worst, lowest at %.0f mm\n", stem.c_str(),
                   robot.name.c_str(), 1000 * check.pelvis_sinking, 1000 * check.lowest_pelvis);
    }
    all_penetrating += check.penetrating_fraction * static_cast<double>(check.frames);
    all_frames += static_cast<double>(check.frames);
    std::fprintf(stderr, "%-10s %-7s %6lld %8.2f %8.1f %8.1f %8.1f %8.3f %8.3f\n",
                 std::filesystem::path(file).stem().c_str(), robot.name.c_str(), static_cast<long long>(check.frames),
                 100 * check.penetrating_fraction, 1000 * check.deepest, 1000 * Quantile(check.drift, 0.5),
                 1000 * Quantile(check.drift, 0.95), check.robot_skating, check.source_skating);
  }
  std::fprintf(stderr, "all %zu contact phases: stance drift median %.1f mm, p95 %.1f mm; planted sole lifted more than 5 mm "
               "in %lld\n", all_drift.size(), 1000 * Quantile(all_drift, 0.5), 1000 * Quantile(all_drift, 0.95),
               static_cast<long long>(LiftedPhases(all_lift)));
  std::fprintf(stderr, "%s: frames with a sole point > 1 cm below the floor: %.1f %% of %.0f\n", robot.name.c_str(),
               100 * all_penetrating / all_frames, all_frames);
  std::fprintf(stderr, "%s: %d of %d trials with at most 1 %% of frames more than 1 cm below the floor, %d with skating "
               "within the source's + 0.05, %d with stance drift within 10 mm median and 25 mm p95\n", robot.name.c_str(),
               floor_met, trials, skating_met, drift_met);
  std::string uneven;
  for (const std::string& walk : uneven_floor_walks) uneven += " " + walk;
  std::fprintf(stderr, "%s: %d of %d walks on a plane floor have a sole within 2 cm of the floor in at least 98 %% of "
               "frames; floor no plane (not levelled):%s\n", robot.name.c_str(), grounded_walks, flat_floor_walks, uneven.c_str());
  EXPECT_EQ(trials, 32);  // the walk and dance rows of index.csv (quoted labels hold commas)
  std::fprintf(stderr, "%s: pelvis at least %.0f mm above the floor, at most %.0f mm under its target\n", robot.name.c_str(),
               1000 * lowest_pelvis, 1000 * pelvis_sinking);
  return {all_drift, all_lift, floor_met, skating_met, drift_met, flat_floor_walks, grounded_walks, uneven_floor_walks,
          lowest_pelvis, pelvis_sinking};
}

// Walking has no flight phase: a robot walk with every sole more than 2 cm above the floor is hovering.
// CMU's capture floors are tilted about 1° (subjects 02, 07, 08 rise 13-21 mm per metre walked); before
// the stage levelled them (2026-11-27), contact detection lost the planted feet at a walk's far end and
// the robot walked up the slope: on G1, 08_04 hovered in 34.5 % of frames, 08_11 15 %, 07_04 19 %, and 8 of
// 17 plane-floor walks more than 2 %; levelled, every one at most 1 %. The walks whose floor is no plane are
// CMU 03_0x (walking over uneven terrain: the stance feet's heights scatter 26-53 mm about any plane); the
// stage leaves them unlevelled, and a flat-floored robot cannot stand where the subject stood on a block.
void ExpectWalksOnTheFloor(const SweepResult& result) {
  EXPECT_GE(result.flat_floor_walks, 17) << "walks whose floor the stage fits a plane";
  EXPECT_EQ(result.grounded_walks, result.flat_floor_walks) << "plane-floor walks with at most 2 % of frames hovering";
  EXPECT_LE(result.uneven_floor_walks.size(), 4u);
}

TEST(RetargetContacts, DemoWalkOntoG1ReportsWhatAnIndependentFkMeasures) {
  SYN_REQUIRE_SHARED("cmu_bvh/02/02_01.bvh");
  const Robot robot = G1();
  const ScratchDir scratch("demo_contacts");
  const std::string markers = CmuMarkers("02/02_01.bvh", scratch.file("walk.markers.h5"));
  RetargetOptions options = CmuOptions(robot);
  options.enforce_contacts = true;
  options.heading_from_pelvis = true;
  RetargetSummary summary;
  const MotionData motion = RetargetFile(markers, options, &summary);
  const ContactCheck check = CheckContacts(motion, robot, testing::IndependentFk(robot.urdf), true);
  EXPECT_GE(check.drift.size(), 4u);  // the walk's steps: the source's contacts are detected
  // The stage's own report agrees with the independent check.
  ExpectSummaryMatches(summary, check);
  std::fprintf(stderr, "stance drift p95 %.1f mm; foot skating: robot %.3f, source %.3f\n", 1000 * Quantile(check.drift, 0.95),
               check.robot_skating, check.source_skating);
  std::fprintf(stderr, "02_01 onto G1: %s\n", summary.BriefReport().c_str());
  // Contacts enforced, issue 17's bounds by the independent FK. Without enforcement this walk
  // had 34 % of frames more than 1 cm below the floor and drift median/p95 45/144 mm.
  ExpectWithinFloorAndDriftBounds(check);
  EXPECT_LE(check.robot_skating, check.source_skating + 0.05);
}

// Held flat through a toe-off, a planted foot makes the leg stretch while the source's knee bends, and the
// knee flexes at once when the foot lifts (CMU 02_01's right knee: -6 to +10 rad/s in one frame). G1's map
// lets planted feet roll with the source about the heel or toe edge by up to max_roll: the knee near the
// phase boundaries moves at about half that speed, no sole point on the floor slides, and the stance
// drift (the sole centre's) stays within issue 17's bounds. All measured by the independent FK.
TEST(RetargetContacts, PlantedFeetRollOffTheirToesInsteadOfSnappingTheKnee) {
  SYN_REQUIRE_SHARED("cmu_bvh/02/02_01.bvh");
  const Robot robot = G1();
  const ScratchDir scratch("roll");
  const std::string markers = CmuMarkers("02/02_01.bvh", scratch.file("walk.markers.h5"));
  const testing::IndependentFk fk(robot.urdf);
  struct Outcome {
    double boundary_knee_speed = 0;  // rad/s, the largest within 4 frames of a contact phase's start or end
    double contact_slide = 0;        // m, the largest step of a sole point on the floor (z < 1 mm) in a phase
    int64_t rolled_frames = 0;       // planted frames whose sole is pitched more than 2°
    ContactCheck check;
  };
  Outcome flat, rolled;
  for (const bool roll : {false, true}) {
    RetargetOptions options = CmuOptions(robot);
    if (!roll) options.max_roll = 0.0;  // else the map's
    const MotionData motion = RetargetFile(markers, options, nullptr);
    Outcome& outcome = roll ? rolled : flat;
    outcome.check = CheckContacts(motion, robot, fk, true);
    const int64_t frames = motion.frames(), nq = motion.nq();
    const size_t feet = robot.foot_links.size();
    ASSERT_EQ(motion.contact_feet.size(), feet);
    std::vector<std::vector<std::vector<Eigen::Vector3d>>> points(feet, std::vector<std::vector<Eigen::Vector3d>>(static_cast<size_t>(frames)));
    for (int64_t t = 0; t < frames; ++t) {
      const auto poses = fk.poses(motion.coordinate_names, &motion.q[static_cast<size_t>(t * nq)], true);
      for (size_t f = 0; f < feet; ++f) {
        const Eigen::Isometry3d& pose = poses.at(robot.foot_links[f]);
        for (const Eigen::Vector3d& p : robot.sole_points[f]) points[f][static_cast<size_t>(t)].push_back(pose * p);
        const auto at = [&](int64_t frame) { return motion.contact[static_cast<size_t>(frame) * feet + f] != 0; };
        if (at(t) && std::abs(pose.linear()(2, 0)) > std::sin(2 * M_PI / 180)) ++outcome.rolled_frames;
        if (t > 0 && at(t) && at(t - 1)) {
          for (size_t k = 0; k < points[f][static_cast<size_t>(t)].size(); ++k) {
            const Eigen::Vector3d& now = points[f][static_cast<size_t>(t)][k];
            const Eigen::Vector3d& before = points[f][static_cast<size_t>(t - 1)][k];
            if (now.z() < 0.001 && before.z() < 0.001) outcome.contact_slide = std::max(outcome.contact_slide, (now - before).head<2>().norm());
          }
        }
      }
    }
    for (size_t f = 0; f < feet; ++f) {
      const std::string knee = motion.contact_feet[f] + "_knee_joint";
      const size_t column = static_cast<size_t>(std::find(motion.coordinate_names.begin(), motion.coordinate_names.end(), knee) -
                                                motion.coordinate_names.begin());
      ASSERT_LT(column, static_cast<size_t>(nq)) << knee;
      for (int64_t t = 1; t < frames; ++t) {
        if ((motion.contact[static_cast<size_t>(t) * feet + f] != 0) == (motion.contact[static_cast<size_t>(t - 1) * feet + f] != 0)) continue;
        for (int64_t s = std::max<int64_t>(1, t - 4); s <= std::min(frames - 1, t + 4); ++s) {
          const double speed = std::abs(motion.q[static_cast<size_t>(s * nq) + column] - motion.q[static_cast<size_t>((s - 1) * nq) + column]) /
                               (motion.time_s[static_cast<size_t>(s)] - motion.time_s[static_cast<size_t>(s - 1)]);
          outcome.boundary_knee_speed = std::max(outcome.boundary_knee_speed, speed);
        }
      }
    }
  }
  std::fprintf(stderr, "02_01 onto G1, flat / rolled: knee near phase boundaries up to %.1f / %.1f rad/s; %lld / %lld planted frames "
               "pitched > 2 deg; sole points on the floor slide up to %.2f / %.2f mm a frame; drift p95 %.1f / %.1f mm\n",
               flat.boundary_knee_speed, rolled.boundary_knee_speed, static_cast<long long>(flat.rolled_frames),
               static_cast<long long>(rolled.rolled_frames), 1000 * flat.contact_slide, 1000 * rolled.contact_slide,
               1000 * Quantile(flat.check.drift, 0.95), 1000 * Quantile(rolled.check.drift, 0.95));
  EXPECT_EQ(flat.rolled_frames, 0);
  EXPECT_GT(rolled.rolled_frames, 0);  // the source's heel strikes and toe-offs
  EXPECT_LT(rolled.boundary_knee_speed, 0.75 * flat.boundary_knee_speed);
  EXPECT_LE(rolled.contact_slide, 0.001);  // the edge a foot rolls about stays put
  EXPECT_LE(Quantile(rolled.check.drift, 0.5), 0.010);
  EXPECT_LE(Quantile(rolled.check.drift, 0.95), 0.025);
  EXPECT_LE(rolled.check.penetrating_fraction, 0.01);
  EXPECT_LE(rolled.check.robot_skating, rolled.check.source_skating + 0.05);
}

// A dancer turning on one foot further than the G1's hip allows (CMU 05_02, frames 725-812: the hip roll on
// its -0.52 rad limit, the ankle pitch on -0.87): with the pelvis held where the tracking put it, the planted
// left foot slid 41 mm and turned 30°; contacts rank above the pelvis task, so the pelvis moves instead.
TEST(RetargetContacts, PelvisMovesWhereAPlantedLegCannotReach) {
  SYN_REQUIRE_SHARED("cmu_bvh/05/05_02.bvh");
  const Robot robot = G1();
  const ScratchDir scratch("pelvis_plant");
  const std::string markers = CmuMarkers("05/05_02.bvh", scratch.file("dance.markers.h5"));
  const testing::IndependentFk fk(robot.urdf);
  ContactCheck held, moved;
  RetargetSummary held_summary, moved_summary;
  for (const bool move : {false, true}) {
    RetargetOptions options = CmuOptions(robot);
    options.enforcement.move_base_for_plants = move;
    RetargetSummary& summary = move ? moved_summary : held_summary;
    const MotionData motion = RetargetFile(markers, options, &summary);
    (move ? moved : held) = CheckContacts(motion, robot, fk, true);
    ExpectSummaryMatches(summary, move ? moved : held);
  }
  std::fprintf(stderr, "05_02 onto G1, pelvis held: drift median/p95 %.1f/%.1f mm; moved: %.1f/%.1f mm (%s)\n",
               1000 * Quantile(held.drift, 0.5), 1000 * Quantile(held.drift, 0.95), 1000 * Quantile(moved.drift, 0.5),
               1000 * Quantile(moved.drift, 0.95), moved_summary.BriefReport().c_str());
  // Held, a plant slides past issue 17's bound (the test shows the case is one); moved, every plant is within it.
  EXPECT_GT(Quantile(held.drift, 0.95), 0.025);
  EXPECT_EQ(held_summary.enforcement.base_moved_frames, 0);
  EXPECT_GT(moved_summary.enforcement.base_moved_frames, 0);
  EXPECT_LE(Quantile(moved.drift, 0.5), 0.010);
  EXPECT_LE(Quantile(moved.drift, 0.95), 0.025);
  EXPECT_LE(moved.penetrating_fraction, 0.01);
  EXPECT_LE(moved.robot_skating, moved.source_skating + 0.05);
}

// G1's hip roll reaches 170° and its yaw ±158°, enough for a second hip solution with the same thigh (pitch + π,
// π − roll, yaw + π). On CMU 60_02 (salsa) the IK slides onto it for a third of the take; the contact
// enforcement's leg solves now bring the planted legs back (since its pelvis search starts each Jacobian
// evaluation from the current answer), but only by tilting the pelvis up to 48°, and before that the planted
// left foot was out of its leg's reach (drift p95 20.5 mm, the pelvis tilted 49°). The robot map's
// [joint_ranges] keeps the hips within a dancer's range, below the mirrored solution, in the IK already.
TEST(RetargetContacts, HipsStayOffTheirMirroredSolution) {
  SYN_REQUIRE_SHARED("cmu_bvh/60/60_02.bvh");
  const Robot robot = G1();
  const ScratchDir scratch("hip_branch");
  const std::string markers = CmuMarkers("60/60_02.bvh", scratch.file("salsa.markers.h5"));
  // The same map without its [joint_ranges] table: the URDF's limits.
  std::string text = ReadFileText(robot.map);
  const size_t table = text.find("[joint_ranges]");
  ASSERT_NE(table, std::string::npos);
  text.erase(table, text.find("\n\n", table) - table);
  const std::string unranged_map = scratch.file("g1_urdf_ranges.toml");
  std::ofstream(unranged_map) << text;
  const testing::IndependentFk fk(robot.urdf);
  struct Outcome {
    double mirrored_fraction = 0, ik_mirrored_fraction = 0, max_tilt = 0;
    ContactCheck check;
  };
  Outcome ranged, unranged;
  for (const bool with_ranges : {false, true}) {
    Outcome& outcome = with_ranges ? ranged : unranged;
    for (const bool enforce : {false, true}) {
      RetargetOptions options = CmuOptions(robot);
      if (!with_ranges) options.robot_map = unranged_map;
      options.enforce_contacts = enforce;
      const MotionData motion = RetargetFile(markers, options, nullptr);
      const auto column = [&](const std::string& joint) {
        return static_cast<size_t>(std::find(motion.coordinate_names.begin(), motion.coordinate_names.end(), joint) -
                                   motion.coordinate_names.begin());
      };
      const size_t nq = motion.coordinate_names.size(), left_roll = column("left_hip_roll_joint"), right_roll = column("right_hip_roll_joint");
      int64_t mirrored = 0;
      for (int64_t t = 0; t < motion.frames(); ++t) {
        const double* q = &motion.q[static_cast<size_t>(t) * nq];
        mirrored += std::abs(q[left_roll]) > M_PI / 2 || std::abs(q[right_roll]) > M_PI / 2;
        // The pelvis's tilt from upright, from its quaternion (w, x, y, z): the z axis's z is 1 − 2(x² + y²).
        if (enforce) outcome.max_tilt = std::max(outcome.max_tilt, std::acos(std::clamp(1 - 2 * (q[1] * q[1] + q[2] * q[2]), -1.0, 1.0)));
      }
      (enforce ? outcome.mirrored_fraction : outcome.ik_mirrored_fraction) = static_cast<double>(mirrored) / static_cast<double>(motion.frames());
      if (enforce) outcome.check = CheckContacts(motion, robot, fk, true);
    }
  }
  std::fprintf(stderr, "60_02 onto G1, URDF ranges: %.0f %% of frames on a mirrored hip after the IK, %.0f %% in the result, pelvis tilt up to %.0f deg, "
               "drift p95 %.1f mm; map ranges: %.0f %%, %.0f %%, %.0f deg, %.1f mm\n", 100 * unranged.ik_mirrored_fraction,
               100 * unranged.mirrored_fraction, unranged.max_tilt * 180 / M_PI, 1000 * Quantile(unranged.check.drift, 0.95),
               100 * ranged.ik_mirrored_fraction, 100 * ranged.mirrored_fraction, ranged.max_tilt * 180 / M_PI,
               1000 * Quantile(ranged.check.drift, 0.95));
  EXPECT_GT(unranged.ik_mirrored_fraction, 0.1);  // the case is one
  EXPECT_EQ(ranged.ik_mirrored_fraction, 0.0);
  EXPECT_EQ(ranged.mirrored_fraction, 0.0);
  EXPECT_LT(ranged.max_tilt, 25 * M_PI / 180);  // a salsa's pelvis stays upright
  EXPECT_LT(ranged.max_tilt, unranged.max_tilt);
  EXPECT_LE(Quantile(ranged.check.drift, 0.5), 0.010);
  EXPECT_LE(Quantile(ranged.check.drift, 0.95), 0.025);
  EXPECT_LE(ranged.check.penetrating_fraction, 0.01);
  EXPECT_LE(ranged.check.robot_skating, ranged.check.source_skating + 0.05);
}

// Swing feet clear the floor as the scaled source's do where the robot's ankle cannot pitch them as the
// source's (contact_enforcement.h, step 3c). HRP-4C's ankle pitch ends at 0.5 rad: on CMU 12_03 its swing
// feet hung toes down, and before the clearance pass 47 % of its unplanted foot-frames were more than 1 cm
// under the source's, the toes dragging over the floor at walking pace (skating 0.728 against the source's
// 0.543); after it, 12 % and 0.541 (12 % and 0.498 with the later blend and plant changes). G1 on 08_07:
// 27 % -> 2 % (4 % now; skating 0.745 -> 0.583, 0.613 now, source 0.831). The
// raise is smooth: the feet's lowest points move about as jerkily as before it (largest frame-to-frame
// second difference 16.0 -> 17.8 mm on HRP-4C's 12_03, 15.9 -> 17.0 on G1's 08_07; raised frame by frame
// in the final pass instead, 36).
TEST(RetargetContacts, SwingFeetClearTheFloorWhereTheAnklesCannotPitchThemAsTheSource) {
#ifdef SYN_SANITIZED_BUILD
  GTEST_SKIP() << "real-data retargets run in the Release test run, not under the sanitizers";
#endif
  SYN_REQUIRE_SHARED("cmu_bvh/12/12_03.bvh");
  SYN_REQUIRE_SHARED("cmu_bvh/08/08_07.bvh");
  SYN_REQUIRE_SHARED("robots/humanoid_synergies/HRP4c_optitrack_model.urdf");
  const ScratchDir scratch("clearance");
  struct Case {
    Robot robot;
    std::string trial;
    bool free_base;
    double under_at_most;
  };
  for (const Case& c : {Case{Hrp4c(), "12/12_03.bvh", false, 0.2}, Case{G1(), "08/08_07.bvh", true, 0.05}}) {
    const std::string markers = CmuMarkers(c.trial, scratch.file(c.robot.name + ".markers.h5"));
    const testing::IndependentFk fk(c.robot.urdf);
    const MotionData motion = RetargetFile(markers, CmuOptions(c.robot), nullptr);
    const ContactCheck check = CheckContacts(motion, c.robot, fk, c.free_base);
    std::fprintf(stderr, "%s onto %s: %.3f of unplanted foot-frames > 1 cm under the source's; skating %.3f (source %.3f); "
                 "lowest sole point's largest second difference %.1f mm\n", c.trial.c_str(), c.robot.name.c_str(),
                 check.swing_under_source, check.robot_skating, check.source_skating, 1000 * check.largest_lowest_second_difference);
    EXPECT_LE(check.swing_under_source, c.under_at_most) << c.robot.name;
    EXPECT_LE(check.robot_skating, check.source_skating + 0.05) << c.robot.name;
    EXPECT_LE(check.largest_lowest_second_difference, 0.025) << c.robot.name;
  }
}

// CMU 03_03, a walk over uneven terrain (stances 5-22 cm above its floor), onto the G1: with its raised
// plants lowered onto the flat floor (terrain_flattening.h) the source's planted feet stand on one level, as
// the robot's must, and the robot follows the body more closely (2026-11-27: P1 median 61.8 -> 46 mm, p95
// 146 -> 129 mm; over the four 03_0x walks onto both robots, median lower on 7 of 8, p95 on all 8).
TEST(RetargetContacts, TerrainWalksAreReplayedOnTheFlatFloor) {
#ifdef SYN_SANITIZED_BUILD
  GTEST_SKIP() << "real-data retargets run in the Release test run, not under the sanitizers";
#endif
  SYN_REQUIRE_SHARED("cmu_bvh/03/03_03.bvh");
  const ScratchDir scratch("terrain");
  const Robot robot = G1();
  const std::string markers = CmuMarkers("03/03_03.bvh", scratch.file("capture.markers.h5"));
  // The spread (p95 - p5) of the source's planted foot heights: the planted frames' foot landmark targets.
  const auto planted_spread = [&](const MotionData& motion) {
    std::vector<double> heights;
    const size_t landmarks = motion.landmark_names.size(), feet = motion.contact_feet.size();
    for (size_t f = 0; f < feet; ++f) {
      const size_t l = LandmarkColumn(motion, motion.contact_feet[f] + "_foot");
      EXPECT_LT(l, landmarks);
      for (int64_t t = 0; t < motion.frames() && l < landmarks; ++t) {
        if (motion.contact[static_cast<size_t>(t) * feet + f] != 0) heights.push_back(motion.landmark_targets[(static_cast<size_t>(t) * landmarks + l) * 7 + 2]);
      }
    }
    return Quantile(heights, 0.95) - Quantile(heights, 0.05);
  };
  RetargetOptions options = CmuOptions(robot);
  RetargetSummary flat, raised;
  const MotionData flattened = RetargetFile(markers, options, &flat);
  options.flatten_terrain = false;
  const MotionData as_captured = RetargetFile(markers, options, &raised);
  std::fprintf(stderr, "03_03 onto G1: planted source feet spread %.0f mm as captured, %.0f mm flattened; P1 median %.1f -> %.1f mm, "
               "p95 %.0f -> %.0f mm\n", 1000 * planted_spread(as_captured), 1000 * planted_spread(flattened),
               1000 * raised.median_position_error[0], 1000 * flat.median_position_error[0], 1000 * raised.p95_position_error[0],
               1000 * flat.p95_position_error[0]);
  EXPECT_GT(planted_spread(as_captured), 0.10);
  EXPECT_LT(planted_spread(flattened), 0.05);
  EXPECT_LT(flat.median_position_error[0], raised.median_position_error[0] - 0.005);
  EXPECT_LT(flat.p95_position_error[0], raised.p95_position_error[0]);
  // The contacts are the capture's either way: flattening moves the landmarks, not what stood on what.
  EXPECT_EQ(flattened.contact, as_captured.contact);
  const ContactCheck check = CheckContacts(flattened, robot, testing::IndependentFk(robot.urdf), true);
  ExpectWithinFloorAndDriftBounds(check);
}

// Per leg (the joints from `foot_link` up to `pelvis_link`, read from the URDF text) the position limits: the
// URDF's, narrowed by the robot map's [joint_ranges]. Independent of the stage's chain and model.
std::map<std::string, std::array<double, 2>> LegLimits(const std::string& urdf, const RobotMap& map, const std::string& foot_link,
                                                       const std::string& pelvis_link) {
  tinyxml2::XMLDocument document;
  EXPECT_EQ(document.LoadFile(urdf.c_str()), tinyxml2::XML_SUCCESS);
  std::map<std::string, const tinyxml2::XMLElement*> joint_of_child;
  for (const tinyxml2::XMLElement* joint = document.RootElement()->FirstChildElement("joint"); joint != nullptr;
       joint = joint->NextSiblingElement("joint")) {
    joint_of_child[joint->FirstChildElement("child")->Attribute("link")] = joint;
  }
  std::map<std::string, std::array<double, 2>> limits;
  for (std::string link = foot_link; link != pelvis_link && joint_of_child.count(link) > 0;) {
    const tinyxml2::XMLElement* joint = joint_of_child.at(link);
    const tinyxml2::XMLElement* limit = joint->FirstChildElement("limit");
    if (std::string(joint->Attribute("type")) != "fixed" && limit != nullptr) {
      std::array<double, 2> range = {limit->DoubleAttribute("lower"), limit->DoubleAttribute("upper")};
      const auto narrowed = map.joint_ranges.find(joint->Attribute("name"));
      if (narrowed != map.joint_ranges.end()) {
        range = {std::max(range[0], narrowed->second[0]), std::min(range[1], narrowed->second[1])};
      }
      limits[joint->Attribute("name")] = range;
    }
    link = joint->FirstChildElement("parent")->Attribute("link");
  }
  return limits;
}

// A stance held with a leg joint on its position limit has no room to move further that way: CMU 09_12's
// turns onto G1 hold a stance ankle on its ±15° roll limit (18 % of its planted foot-frames, session 51; the
// 18 straight CMU walks none). syn-retarget reports how many planted foot-frames do; an independent count
// over the output's q, the source's contacts and the limits read from the URDF text and the map agrees,
// joint by joint.
TEST(RetargetContacts, StancesOnAJointLimitAreCountedAsTheUrdfsLimitsFindThem) {
#ifdef SYN_SANITIZED_BUILD
  GTEST_SKIP() << "real-data retargets run in the Release test run, not under the sanitizers";
#endif
  SYN_REQUIRE_SHARED("cmu_bvh/09/09_12.bvh");
  const ScratchDir scratch("stance_limits");
  const Robot robot = G1();
  RetargetSummary summary;
  const MotionData motion = RetargetFile(CmuMarkers("09/09_12.bvh", scratch.file("capture.markers.h5")), CmuOptions(robot), &summary);
  const RobotMap map = LoadRobotMap(robot.map);
  const size_t nq = motion.coordinate_names.size(), feet = motion.contact_feet.size();
  ASSERT_EQ(feet, robot.foot_links.size());
  int64_t planted = 0, limited = 0;
  std::map<std::string, int64_t> per_joint;
  for (size_t f = 0; f < feet; ++f) {
    const auto limits = LegLimits(robot.urdf, map, robot.foot_links[f], robot.pelvis_link);
    EXPECT_EQ(limits.size(), 6u);  // hip pitch, roll, yaw, knee, ankle pitch, roll
    std::map<std::string, size_t> column;  // each leg joint's column of q
    for (const auto& [joint, range] : limits) {
      column[joint] = static_cast<size_t>(std::find(motion.coordinate_names.begin(), motion.coordinate_names.end(), joint) -
                                          motion.coordinate_names.begin());
      ASSERT_LT(column[joint], nq) << joint;
    }
    for (int64_t t = 0; t < motion.frames(); ++t) {
      if (motion.contact[static_cast<size_t>(t) * feet + f] == 0) continue;
      ++planted;
      bool any = false;
      for (const auto& [joint, range] : limits) {
        const double value = motion.q[static_cast<size_t>(t) * nq + column.at(joint)];
        if (value - range[0] < kStanceLimitBand || range[1] - value < kStanceLimitBand) any = true, ++per_joint[joint];
      }
      limited += any ? 1 : 0;
    }
  }
  const auto most = std::max_element(per_joint.begin(), per_joint.end(), [](const auto& a, const auto& b) { return a.second < b.second; });
  std::fprintf(stderr, "09_12 onto G1: planted legs with a joint on its limit in %lld of %lld planted foot-frames (most %s, %lld)\n",
               static_cast<long long>(limited), static_cast<long long>(planted),
               most == per_joint.end() ? "none" : most->first.c_str(), static_cast<long long>(most == per_joint.end() ? 0 : most->second));
  EXPECT_EQ(summary.enforcement.planted_foot_frames, planted);
  EXPECT_EQ(summary.enforcement.limited_stance_frames, limited);
  ASSERT_NE(most, per_joint.end());
  EXPECT_EQ(summary.enforcement.most_limited_joint, most->first);
  EXPECT_EQ(summary.enforcement.most_limited_joint_frames, most->second);
  EXPECT_GT(limited, planted / 20);  // the turns are such stances
  EXPECT_NE(summary.BriefReport().find("planted legs with a joint on its limit in " + std::to_string(limited)), std::string::npos);
}

// CMU 94_07's right foot swivels 200° about the vertical in 50 ms (a twist in the BVH flipping) and stays
// turned for most of the take; no G1 leg turns its foot that far from its pelvis (hip yaw ±1.2 rad). Followed,
// the IK bent the leg onto its limits to turn the foot a little further, and the robot's pelvis ended up to
// 0.8 m under its target, on the floor, while the dancer stood. Held within the leg's turn
// (foot_yaw_range.h), the pelvis tracks, and every plant of the take is within issue 17's drift bounds. The
// pelvis and the soles by the independent FK.
TEST(RetargetContacts, AFootTurnedFurtherThanTheLegTurnsDoesNotContortTheLeg) {
#ifdef SYN_SANITIZED_BUILD
  GTEST_SKIP() << "real-data retargets run in the Release test run, not under the sanitizers";
#endif
  SYN_REQUIRE_SHARED("cmu_bvh/94/94_07.bvh");
  const ScratchDir scratch("foot_yaw");
  const Robot robot = G1();
  const testing::IndependentFk fk(robot.urdf);
  const std::string markers = CmuMarkers("94/94_07.bvh", scratch.file("capture.markers.h5"));
  // The share of frames whose pelvis link is more than 0.2 m from its target.
  const auto pelvis_off = [&](const MotionData& motion) {
    const size_t landmarks = motion.landmark_names.size();
    const size_t pelvis = LandmarkColumn(motion, "pelvis");
    EXPECT_LT(pelvis, landmarks);
    int64_t off = 0;
    for (int64_t t = 0; t < motion.frames() && pelvis < landmarks; ++t) {
      const auto poses = fk.poses(motion.coordinate_names, &motion.q[static_cast<size_t>(t * motion.nq())], true);
      off += (poses.at("pelvis").translation() - TargetPosition(motion, t, pelvis)).norm() > 0.2;
    }
    return static_cast<double>(off) / static_cast<double>(motion.frames());
  };
  RetargetOptions options = CmuOptions(robot);
  RetargetSummary held_summary, followed_summary;
  const MotionData held = RetargetFile(markers, options, &held_summary);
  options.hold_foot_yaw = false;
  const MotionData followed = RetargetFile(markers, options, &followed_summary);
  const double held_off = pelvis_off(held), followed_off = pelvis_off(followed);
  const ContactCheck check = CheckContacts(held, robot, fk, true), followed_check = CheckContacts(followed, robot, fk, true);
  std::fprintf(stderr, "94_07 onto G1: pelvis more than 0.2 m off its target in %.1f %% of frames (%.1f %% following the feet's "
               "turn); P1 median/p95 %.1f/%.0f mm (%.1f/%.0f); stance drift p95 %.1f mm (%.1f)\n", 100 * held_off,
               100 * followed_off, 1000 * held_summary.median_position_error[0], 1000 * held_summary.p95_position_error[0],
               1000 * followed_summary.median_position_error[0], 1000 * followed_summary.p95_position_error[0],
               1000 * Quantile(check.drift, 0.95), 1000 * Quantile(followed_check.drift, 0.95));
  EXPECT_GT(followed_off, 0.3);  // the case is one
  EXPECT_LT(held_off, 0.02);
  EXPECT_LT(held_summary.p95_position_error[0], 0.5 * followed_summary.p95_position_error[0]);
  ExpectWithinFloorAndDriftBounds(check);
}

TEST(RetargetContacts, EveryCmuWalkAndDanceOntoG1) {
#ifdef SYN_SANITIZED_BUILD
  GTEST_SKIP() << "the real-data contact sweep runs in the Release test run, not under the sanitizers";
#endif
  SYN_REQUIRE_SHARED("cmu_bvh/index.csv");
  const SweepResult result = CheckEveryWalkAndDance(G1(), true);
  // Issue 17 asks for every trial. Measured 2026-11-26: all 32 meet the floor, skating and drift bounds
  // (stance drift over all 430 phases 0.0/1.3 mm median/p95). What got them there, in order: the pelvis moved
  // for plants out of reach (drift 27 -> 30 trials, all-phase p95 20.0 -> 10.9 mm), straight knees re-bent and
  // swing feet at the source's clearance (05_11 57 -> 5 mm, 08_07's skating 0.861 -> 0.844), G1's hips kept
  // off their mirrored solution by the map's [joint_ranges] (60_02 20.5 -> 0.7 mm, p95 2.9 mm), and the pelvis
  // moved frame by frame where a planted leg still could not hold its plant (94_07 41 -> 24.6 mm: borderline).
  // Since the ingest drops the ease-in some BVH copies blend from the T-pose into the take with, and the scale
  // is the subject's standing height in that T-pose (2026-11-26), skating is met on 30 (the dances 94_07:
  // 0.558 against 0.499, 94_15: 0.438 against 0.365; both met before, the source's own figure moving
  // most: 94_15's 0.456 -> 0.365) and drift on 31 (94_07, p95 91.8 mm), while the P1 error fell (mean over the
  // 32 trials 36.7 -> 30.3 mm; 12_01-03 and 10_04, no longer crouched, 45 -> 20 mm).
  // Since swing feet keep the source's clearance where the ankles cannot pitch them as the source
  // (2026-11-27), skating is met on all 32 (94_07 0.558 -> 0.517, 94_15 0.438 -> 0.370; 08_07 0.745 -> 0.583).
  // The same plant fix took the stance drift over all 430 phases from 1.5/5.0 to 1.5/3.4 mm (94_07 still
  // 52.9 mm p95, its deep squat past G1's ankle).
  // Since feet turned further than the leg turns are held at its limit (foot_yaw_range.h, session 30),
  // 94_07 is within the drift bounds (47.9 -> 2.1 mm p95; test above): every trial within every bound.
  // Guarded a trial below today's counts, so that a different machine's rounding on a borderline trial does
  // not fail it, and the stance drift over all phases: median within the bound, p95 under 10 mm.
  EXPECT_GE(result.floor_met, 31);
  EXPECT_GE(result.skating_met, 31);
  EXPECT_GE(result.drift_met, 31);
  ExpectWalksOnTheFloor(result);
  EXPECT_LE(Quantile(result.drift, 0.5), 0.010);
  EXPECT_LE(Quantile(result.drift, 0.95), 0.010);
  // The stance sole stays on the floor (issue 17: flat on z = 0), which drift, floor and skating do not
  // see. Phases whose planted sole rose more than 5 mm, of 560: 36 until the base came down onto a planted
  // foot left in the air (2026-11-27), 19 since (94_15 48 mm: a kick the floor rounds lift the base for).
  EXPECT_LE(LiftedPhases(result.lift), 23);
  // The pelvis by the independent FK (session 30): at least 0.31 m above the floor (94_07's squat) and at most
  // 0.24 m under its target (60_10; the contacts lower the base where a planted leg cannot reach). Before the
  // feet's turns were held, 94_07's went to -0.02 m, 0.80 m under its target.
  EXPECT_GE(result.lowest_pelvis, 0.25);
  EXPECT_LE(result.pelvis_sinking, 0.3);
}

TEST(RetargetContacts, EveryCmuWalkAndDanceOntoHrp4c) {
#ifdef SYN_SANITIZED_BUILD
  GTEST_SKIP() << "the real-data contact sweep runs in the Release test run, not under the sanitizers";
#endif
  SYN_REQUIRE_SHARED("cmu_bvh/index.csv");
  SYN_REQUIRE_SHARED("robots/humanoid_synergies/HRP4c_optitrack_model.urdf");
  const SweepResult result = CheckEveryWalkAndDance(Hrp4c(), false);  // the stage's figures against the independent check
  // Not yet every trial within issue 17's bounds. HRP-4C's URDF speeds (1.9-3 rad/s) are under a person's
  // pace. Within them, measured 2026-11-26 over all 430 phases, stance drift median/p95: 37.5/239 mm; planting
  // each phase where the foot touched down, 23.2/156 (trials within the drift bounds 1 -> 4, skating 12 -> 14);
  // moving its virtual base for plants and, frame by frame, where a planted leg cannot hold within its speed,
  // 12.4/82 (drift 4 trials, skating 20, floor 32). With its map's velocity_limit_scale of 4 and max_roll of
  // 0.2 (hrp4c.toml), 2026-11-26: 2.1/12.5 mm, drift 30 trials, skating 26 (walks whose swing feet the scaled
  // source lifts at the same pace the robot drags over the floor: 05_01, 08_07, 12_01-03), floor 32.
  // Swing feet raised to the source's clearance where the ankle (pitch within 0.5 rad) leaves them toes down
  // (2026-11-27): skating 25 -> 30 (05_01 0.692 -> 0.560, 07_04 0.659 -> 0.483, 08_07 0.805 -> 0.586, 12_03
  // 0.728 -> 0.541, 60_12 0.594 -> 0.508; still over: 10_04 0.712 against 0.595, 12_01 0.785 against 0.731),
  // drift 31 (05_02, median 13.5 mm), floor 32. The plants' horizontal correction fading over 0.3 s
  // instead of 0.1 (2026-11-27): skating 32 (10_04 0.645 against 0.595: borderline; 12_01 0.733 against
  // 0.731). A plant moved to where its foot touched down keeping the plan's own pitch instead of the
  // touchdown's tilt (2026-11-27): drift 32 (05_02 13.5 -> 7.0 mm median), all phases 1.9/8.9 -> 1.8/4.7 mm,
  // skating 32 (10_04 0.619 against 0.595). Every trial within every bound. Guarded with a margin against
  // regressions.
  // 2026-11-28: contacts on uneven ground (contact_detection.h) give CMU subject 03's terrain walks a
  // contact phase in every stance (before, 03_02 had none in its first 1.5 s and the robot's feet were
  // free there). HRP-4C's 03_02 first right stance (0.2-0.66 s, the source's ankle 20-24 cm up and rising)
  // then drifts 76 mm: planted on the floor, 17 cm under the source's foot, its leg cannot hold it (base
  // lowered up to 126 mm), after a 1 m step of the left foot that straightens the right knee; median
  // 7.6 mm. Drift 31 -> 30 (05_11 and 03_02), skating 31 (03_02: 0.356 against the source's 0.279).
  // 2026-11-27 (session 28): the pelvis moves for plants smoothed over ±0.05 s, not ±0.1 (hrp4c.toml's
  // base_smoothing): 05_11's spin-kick plant 28.1 -> 14.2 mm p95, drift 30 -> 31; lifted phases 40 -> 32.
  // Terrain walks replayed on the flat floor (terrain_flattening.h, 2026-11-27): skating 31 -> 32 (03_02 0.441
  // against its flattened source's 0.422), 03_02's first right stance still drifts (72 mm p95, its knee
  // straightened on the branch bound under a pelvis 0.1 m out of reach).
  // Session 30: 03_02's first frame, a T-pose, no longer the arms' reference (stance_alignment.h
  // NeutralReference): its hands had been asked to cross in front of the knees, and the IK crouched for them.
  // Its right stance 72.3 -> 5.1 mm p95: drift 32, every trial within every bound. Since syn-ingest drops
  // 03_02's T-pose lead-in (bvh_reader.cpp), its first frame is a walking one: 4.0 mm p95.
  EXPECT_EQ(result.floor_met, 32);
  EXPECT_GE(result.drift_met, 31);
  ExpectWalksOnTheFloor(result);
  EXPECT_GE(result.skating_met, 31);
  EXPECT_LE(Quantile(result.drift, 0.5), 0.005);
  EXPECT_LE(Quantile(result.drift, 0.95), 0.020);
  // Phases whose planted sole rose more than 5 mm, of 560 (see the G1 sweep): 51 -> 45, most of those left
  // a slow leg still bringing its foot down in the phase's first frames; 40 since the BVH reader drops a
  // frame that leaves a joint at rest (05_01, 08_04 and 03_01 start one frame later); 32 with the map's
  // sharper pelvis moves for plants.
  EXPECT_LE(LiftedPhases(result.lift), 36);
  // The pelvis (session 30): at least 0.42 m above the floor, and at most 0.52 m under its target: CMU
  // 94_15's leaps, whose pelvis targets rise 1.0 m above the planted foot, past HRP-4C's legs, and which its
  // legs, bent 107° at take-off and held to 4 times their URDF speed, do not straighten for in time.
  EXPECT_GE(result.lowest_pelvis, 0.4);
  EXPECT_LE(result.pelvis_sinking, 0.6);
}

}  // namespace
}  // namespace syn
