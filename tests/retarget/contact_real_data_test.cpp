// Contact-consistent retargeting on real data, checked with a forward kinematics independent of the
// stage (tests/support/independent_fk.h, from the URDF text):
// - every shared CMU walk and dance trial onto the G1 and the HRP-4C: no sole point more than 1 cm below
//   the floor in more than 1 % of frames; during the source's contact phases the robot's stance sole
//   drifts ≤ 10 mm median and ≤ 25 mm p95; the GMD foot-skating ratio of the robot is at most the same
//   measure on the source's foot targets (the capture scaled to the robot) + 0.05;
// - a same-robot round trip: the shared G1 motions turned into virtual link markers and retargeted back
//   onto the G1 give back their joint angles.
#include <gtest/gtest.h>

#include <algorithm>
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

#include "common/intermediate_file.h"
#include "common/markers_file.h"
#include "common/foot_sliding.h"
#include "stages/ingest/ingest.h"
#include "stages/retarget/retarget.h"
#include "tests/support/demo_motion.h"
#include "tests/support/independent_fk.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

double Quantile(std::vector<double> values, double q) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  return values[std::min(values.size() - 1, static_cast<size_t>(q * static_cast<double>(values.size() - 1) + 0.5))];
}

std::vector<std::string> SplitCsv(const std::string& line) {
  std::vector<std::string> cells(1);
  bool quoted = false;
  for (char c : line) {
    if (c == '"') quoted = !quoted;
    else if (c == ',' && !quoted) cells.emplace_back();
    else cells.back() += c;
  }
  return cells;
}

// The shared CMU trials of the given classes (index.csv's motion_class).
std::vector<std::string> CmuTrials(const std::vector<std::string>& classes) {
  std::ifstream in(testing::SharedPath("cmu_bvh/index.csv"));
  std::string line;
  std::getline(in, line);
  std::vector<std::string> files;
  while (std::getline(in, line)) {
    const std::vector<std::string> cells = SplitCsv(line);
    if (std::find(classes.begin(), classes.end(), cells[4]) != classes.end()) files.push_back(cells[2]);
  }
  return files;
}

struct Robot {
  std::string name, urdf, map;
  std::vector<std::string> foot_links;
  std::vector<std::vector<Eigen::Vector3d>> sole_points;  // per foot, link frame (from the robot map text)
};

Robot G1() {
  const std::vector<Eigen::Vector3d> sole = {{-0.05, 0.025, -0.035}, {-0.05, -0.025, -0.035}, {0.12, 0.03, -0.035}, {0.12, -0.03, -0.035}};
  return {"G1", testing::SourcePath(testing::kG1Urdf), testing::SourcePath(testing::kG1Map),
          {"left_ankle_roll_link", "right_ankle_roll_link"}, {sole, sole}};
}

Robot Hrp4c() {
  const std::vector<Eigen::Vector3d> sole = {{-0.02, 0.05, -0.08}, {-0.02, -0.05, -0.08}, {0.18, 0.05, -0.08}, {0.18, -0.05, -0.08}};
  return {"HRP-4C", testing::SharedPath("robots/humanoid_synergies/HRP4c_optitrack_model.urdf"),
          testing::SourcePath("manifests/robots/hrp4c.toml"), {"LL_foot", "RL_foot"}, {sole, sole}};
}

struct ContactCheck {
  int64_t frames = 0;
  double penetrating_fraction = 0;  // frames with a sole point > 1 cm below z = 0
  double deepest = 0;               // m below z = 0
  std::vector<double> drift;        // per source contact phase, m
  double robot_skating = 0, source_skating = 0;
};

// Checks a retargeted motion with the independent FK.
ContactCheck CheckContacts(const MotionData& motion, const Robot& robot, const testing::IndependentFk& fk, bool free_base) {
  ContactCheck check;
  const int64_t frames = motion.frames(), nq = motion.nq();
  const size_t feet = robot.foot_links.size();
  check.frames = frames;
  // Sole points per frame and foot.
  std::vector<std::vector<FootSample>> robot_feet(feet), source_feet(feet);
  std::vector<std::vector<Eigen::Vector2d>> centre(feet);
  int64_t penetrating = 0;
  for (int64_t t = 0; t < frames; ++t) {
    const auto poses = fk.poses(motion.coordinate_names, &motion.q[static_cast<size_t>(t * nq)], free_base);
    double lowest_frame = 1e9;
    for (size_t f = 0; f < feet; ++f) {
      const Eigen::Isometry3d& pose = poses.at(robot.foot_links[f]);
      FootSample sample;
      sample.lowest_z = 1e9;
      for (const Eigen::Vector3d& point : robot.sole_points[f]) {
        const Eigen::Vector3d world = pose * point;
        sample.x += world.x() / static_cast<double>(robot.sole_points[f].size());
        sample.y += world.y() / static_cast<double>(robot.sole_points[f].size());
        sample.lowest_z = std::min(sample.lowest_z, world.z());
      }
      lowest_frame = std::min(lowest_frame, sample.lowest_z);
      robot_feet[f].push_back(sample);
      centre[f].emplace_back(sample.x, sample.y);
    }
    if (lowest_frame < -0.01) ++penetrating;
    check.deepest = std::max(check.deepest, -lowest_frame);
  }
  check.penetrating_fraction = static_cast<double>(penetrating) / static_cast<double>(frames);
  // Drift: within each contact phase of the source, the largest horizontal distance of the sole centre
  // from where it was when the phase began.
  EXPECT_EQ(motion.contact_feet.size(), feet);
  for (size_t f = 0; f < feet && motion.contact_feet.size() == feet; ++f) {
    int64_t begin = -1;
    double drift = 0;
    for (int64_t t = 0; t <= frames; ++t) {
      const bool planted = t < frames && motion.contact[static_cast<size_t>(t) * feet + f] != 0;
      if (planted && begin < 0) begin = t, drift = 0;
      if (planted) drift = std::max(drift, (centre[f][static_cast<size_t>(t)] - centre[f][static_cast<size_t>(begin)]).norm());
      if (!planted && begin >= 0) check.drift.push_back(drift), begin = -1;
    }
  }
  // The source's feet, scaled to the robot: the foot landmark targets, heights above their planted level.
  const size_t landmarks = motion.landmark_names.size();
  for (size_t f = 0; f < feet; ++f) {
    const std::string name = f == 0 ? "left_foot" : "right_foot";
    const size_t l = static_cast<size_t>(std::find(motion.landmark_names.begin(), motion.landmark_names.end(), name) -
                                         motion.landmark_names.begin());
    EXPECT_LT(l, landmarks);
    std::vector<double> heights;
    for (int64_t t = 0; t < frames; ++t) heights.push_back(motion.landmark_targets[(static_cast<size_t>(t) * landmarks + l) * 7 + 2]);
    const double planted_level = Quantile(heights, 0.02);
    for (int64_t t = 0; t < frames; ++t) {
      const double* target = &motion.landmark_targets[(static_cast<size_t>(t) * landmarks + l) * 7];
      FootSample sample;
      sample.x = target[0], sample.y = target[1], sample.lowest_z = target[2] - planted_level;
      source_feet[f].push_back(sample);
    }
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
  return check;
}

std::string WriteMarkers(const MarkerData& data, const std::string& path) {
  IntermediateWriter writer(path, {kMarkersSchema, kMarkersSchemaVersion, "test", {}, nlohmann::json::array()});
  WriteMarkerData(writer, data);
  writer.commit();
  return path;
}

void CheckEveryWalkAndDance(const Robot& robot, bool free_base) {
  const std::string dir = std::filesystem::temp_directory_path() / ("syn_contacts_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const testing::IndependentFk fk(robot.urdf);
  std::vector<double> all_drift;
  std::fprintf(stderr, "%-10s %-7s %6s %8s %8s %8s %8s %8s %8s\n", "trial", "robot", "frames", "pen>1cm%", "deepest",
               "drift50", "drift95", "skate", "source");
  int trials = 0;
  for (const std::string& file : CmuTrials({"walk", "dance"})) {
    SCOPED_TRACE(file + " onto " + robot.name);
    IngestOptions ingest;
    ingest.drop_first_frame = file.find("_excerpt") == std::string::npos;
    const std::string markers =
        WriteMarkers(IngestCapture(testing::SharedPath("cmu_bvh/" + file), ingest, nullptr), dir + "/capture.markers.h5");
    RetargetOptions options;
    options.model = robot.urdf;
    options.robot_map = robot.map;
    options.markerset = testing::SourcePath("manifests/markersets/cmu-bvh.toml");
    RetargetSummary summary;
    const MotionData motion = RetargetFile(markers, options, &summary);
    const ContactCheck check = CheckContacts(motion, robot, fk, free_base);
    ++trials;
    EXPECT_LE(check.penetrating_fraction, 0.01);
    if (!check.drift.empty()) {
      EXPECT_LE(Quantile(check.drift, 0.5), 0.010);
      EXPECT_LE(Quantile(check.drift, 0.95), 0.025);
    }
    EXPECT_LE(check.robot_skating, check.source_skating + 0.05);
    all_drift.insert(all_drift.end(), check.drift.begin(), check.drift.end());
    std::fprintf(stderr, "%-10s %-7s %6lld %8.2f %8.1f %8.1f %8.1f %8.3f %8.3f\n",
                 std::filesystem::path(file).stem().c_str(), robot.name.c_str(), static_cast<long long>(check.frames),
                 100 * check.penetrating_fraction, 1000 * check.deepest, 1000 * Quantile(check.drift, 0.5),
                 1000 * Quantile(check.drift, 0.95), check.robot_skating, check.source_skating);
  }
  std::fprintf(stderr, "all %zu contact phases: stance drift median %.1f mm, p95 %.1f mm\n", all_drift.size(),
               1000 * Quantile(all_drift, 0.5), 1000 * Quantile(all_drift, 0.95));
  EXPECT_EQ(trials, 32);  // the walk and dance rows of index.csv (quoted labels hold commas)
  std::filesystem::remove_all(dir);
}

TEST(RetargetContacts, DemoWalkOntoG1KeepsFeetPlantedAndAboveTheFloor) {
  SYN_REQUIRE_SHARED("cmu_bvh/02/02_01.bvh");
  const Robot robot = G1();
  const std::string dir = std::filesystem::temp_directory_path() / ("syn_demo_contacts_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  IngestOptions ingest;
  ingest.drop_first_frame = true;
  const std::string markers =
      WriteMarkers(IngestCapture(testing::SharedPath("cmu_bvh/02/02_01.bvh"), ingest, nullptr), dir + "/walk.markers.h5");
  RetargetOptions options;
  options.model = robot.urdf;
  options.robot_map = robot.map;
  options.markerset = testing::SourcePath("manifests/markersets/cmu-bvh.toml");
  RetargetSummary summary;
  const MotionData motion = RetargetFile(markers, options, &summary);
  std::filesystem::remove_all(dir);
  const ContactCheck check = CheckContacts(motion, robot, testing::IndependentFk(robot.urdf), true);
  EXPECT_GE(check.drift.size(), 4u);
  EXPECT_LE(check.penetrating_fraction, 0.01);
  EXPECT_LE(check.deepest, 0.01);
  EXPECT_LE(Quantile(check.drift, 0.5), 0.010);
  EXPECT_LE(Quantile(check.drift, 0.95), 0.025);
  EXPECT_LE(check.robot_skating, check.source_skating + 0.05);
  // The stage's own report agrees with the independent check.
  EXPECT_NEAR(summary.deepest_penetration, check.deepest, 2e-3);
  EXPECT_EQ(summary.contact_phases.size(), check.drift.size());
  std::fprintf(stderr, "02_01 onto G1: %s\n", summary.BriefReport().c_str());
}

TEST(RetargetContacts, EveryCmuWalkAndDanceOntoG1) {
#ifdef SYN_SANITIZED_BUILD
  GTEST_SKIP() << "the real-data contact sweep runs in the Release test run, not under the sanitizers";
#endif
  SYN_REQUIRE_SHARED("cmu_bvh/index.csv");
  CheckEveryWalkAndDance(G1(), true);
}

TEST(RetargetContacts, EveryCmuWalkAndDanceOntoHrp4c) {
#ifdef SYN_SANITIZED_BUILD
  GTEST_SKIP() << "the real-data contact sweep runs in the Release test run, not under the sanitizers";
#endif
  SYN_REQUIRE_SHARED("cmu_bvh/index.csv");
  SYN_REQUIRE_SHARED("robots/humanoid_synergies/HRP4c_optitrack_model.urdf");
  CheckEveryWalkAndDance(Hrp4c(), false);
}

// Same-robot round trip: a G1 motion (root pose + 29 joints) turned into virtual markers on the tracked
// links (link origin, and 0.1 m along the link's x and y axes), after one zero-pose frame as the
// reference stance, retargeted back onto the G1 with --reference-time 0.
constexpr const char* kVirtualMarkerSet = R"toml(name = "g1-virtual"
description = "virtual markers on G1 links (test fixture)"
)toml";
const std::vector<std::pair<std::string, std::string>> kVirtualLandmarks = {
    {"pelvis", "pelvis"}, {"left_foot", "left_ankle_roll_link"}, {"right_foot", "right_ankle_roll_link"},
    {"left_hand", "left_rubber_hand"}, {"right_hand", "right_rubber_hand"}, {"head", "head_link"},
    {"upper_torso", "torso_link"}, {"left_elbow", "left_elbow_link"}, {"right_elbow", "right_elbow_link"}};

void RoundTrip(const std::string& name, bool contacts, double* p95_deg, double* max_deg, std::string* worst) {
  const std::string urdf = testing::SourcePath(testing::kG1Urdf);
  const testing::IndependentFk fk(urdf);
  const std::vector<std::string>& joints = fk.revoluteJointsInFileOrder();
  ASSERT_EQ(joints.size(), 29u);
  // The CSV: per row root x y z, root quaternion w x y z, 29 joint angles.
  std::ifstream in(testing::SharedPath("robot_motion/g1_kimodo_" + name + ".csv"));
  std::vector<std::vector<double>> rows;
  std::string line;
  while (std::getline(in, line)) {
    std::vector<double> row;
    for (const std::string& cell : SplitCsv(line)) row.push_back(std::stod(cell));
    ASSERT_EQ(row.size(), 36u);
    rows.push_back(row);
  }
  // The zero pose, standing on the floor: the reference stance.
  {
    std::vector<double> zero(36, 0.0);
    zero[3] = 1.0;
    const auto poses = fk.poses(std::map<std::string, double>{}, Eigen::Isometry3d::Identity());
    double lowest = 1e9;
    for (const char* foot : {"left_ankle_roll_link", "right_ankle_roll_link"}) {
      lowest = std::min(lowest, poses.at(foot).translation().z() - 0.035);
    }
    zero[0] = rows[0][0], zero[1] = rows[0][1], zero[2] = -lowest;
    rows.insert(rows.begin(), zero);
  }
  MarkerData data;
  data.rate_hz = 30.0;
  data.up_axis = 'z';
  std::string marker_set = kVirtualMarkerSet;
  for (const auto& [landmark, link] : kVirtualLandmarks) {
    for (const char* suffix : {"_o", "_x", "_y"}) data.labels.push_back(landmark + suffix);
    marker_set += "\n[[landmark]]\nname = \"" + landmark + "\"\norigin = [\"" + landmark + "_o\"]\nprimary = \"x\"\n" +
                  "x = { from = [\"" + landmark + "_o\"], to = [\"" + landmark + "_x\"] }\n" +
                  "y = { from = [\"" + landmark + "_o\"], to = [\"" + landmark + "_y\"] }\n";
  }
  for (size_t t = 0; t < rows.size(); ++t) {
    const std::vector<double>& row = rows[t];
    data.time_s.push_back(static_cast<double>(t) / data.rate_hz);
    Eigen::Isometry3d root = Eigen::Isometry3d::Identity();
    root.translation() = Eigen::Vector3d(row[0], row[1], row[2]);
    root.linear() = Eigen::Quaterniond(row[3], row[4], row[5], row[6]).normalized().toRotationMatrix();
    std::map<std::string, double> values;
    for (size_t j = 0; j < 29; ++j) values[joints[j]] = row[7 + j];
    const auto poses = fk.poses(values, root);
    for (const auto& [landmark, link] : kVirtualLandmarks) {
      const Eigen::Isometry3d& pose = poses.at(link);
      for (const Eigen::Vector3d& point : {Eigen::Vector3d(0, 0, 0), Eigen::Vector3d(0.1, 0, 0), Eigen::Vector3d(0, 0.1, 0)}) {
        const Eigen::Vector3d world = pose * point;
        data.points.insert(data.points.end(), {world.x(), world.y(), world.z()});
      }
    }
  }
  const std::string dir = std::filesystem::temp_directory_path() /
                          ("syn_round_trip_" + name + (contacts ? "_on_" : "_off_") + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string markers = WriteMarkers(data, dir + "/g1.markers.h5");
  { std::ofstream(dir + "/g1-virtual.toml") << marker_set; }
  RetargetOptions options;
  options.model = urdf;
  options.robot_map = testing::SourcePath(testing::kG1Map);
  options.markerset = dir + "/g1-virtual.toml";
  options.reference_time = 0.0;
  options.contacts = contacts;
  RetargetSummary summary;
  const MotionData motion = RetargetFile(markers, options, &summary);
  // SYN_KEEP_ROUND_TRIP=1 keeps the virtual markers and marker set, to run syn-retarget -v on them.
  if (std::getenv("SYN_KEEP_ROUND_TRIP")) std::fprintf(stderr, "kept %s\n", dir.c_str());
  else std::filesystem::remove_all(dir);
  EXPECT_NEAR(summary.scale, 1.0, 1e-6);
  std::vector<double> errors;
  double largest = 0;
  for (size_t t = 11; t < rows.size(); ++t) {  // after the reference frame and the first 10 frames
    for (size_t j = 0; j < 29; ++j) {
      const size_t i = static_cast<size_t>(std::find(motion.coordinate_names.begin(), motion.coordinate_names.end(), joints[j]) -
                                           motion.coordinate_names.begin());
      const double error = std::abs(motion.q[t * static_cast<size_t>(motion.nq()) + i] - rows[t][7 + j]) * 180.0 / M_PI;
      errors.push_back(error);
      if (error > largest) largest = error, *worst = joints[j] + " frame " + std::to_string(t);
    }
  }
  *p95_deg = Quantile(errors, 0.95);
  *max_deg = largest;
  std::fprintf(stderr, "round trip %s (contacts %s): joint error median %.3f p95 %.3f max %.3f deg (%s); %s\n", name.c_str(), contacts ? "on" : "off",
               Quantile(errors, 0.5), *p95_deg, *max_deg, worst->c_str(), summary.BriefReport().c_str());
}

TEST(RetargetRoundTrip, SharedG1MotionsComeBackToTheirJointAngles) {
  SYN_REQUIRE_SHARED("robot_motion/g1_kimodo_walk.csv");
  for (const char* name : {"walk", "dance", "jumpjack"}) {
    SCOPED_TRACE(name);
    double p95 = 0, largest = 0;
    std::string worst;
    RoundTrip(name, true, &p95, &largest, &worst);
    EXPECT_LE(p95, 0.5);
    EXPECT_LE(largest, 2.0) << worst;
  }
}

// The same without the contact constraints: the knee branch (posture_target) alone.
TEST(RetargetRoundTrip, WithoutContactConstraintsKneesStayOnTheirBranch) {
  SYN_REQUIRE_SHARED("robot_motion/g1_kimodo_walk.csv");
  for (const char* name : {"walk", "dance", "jumpjack"}) {
    SCOPED_TRACE(name);
    double p95 = 0, largest = 0;
    std::string worst;
    RoundTrip(name, false, &p95, &largest, &worst);
    EXPECT_LE(p95, 0.5);
    EXPECT_LE(largest, 2.0) << worst;
  }
}

}  // namespace
}  // namespace syn
