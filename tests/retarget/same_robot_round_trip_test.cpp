// Same-robot round trip (issue 17, "Must show"): a real G1 motion turned into markers on the G1 itself must
// retarget back onto the G1 to its own joint angles. With source and target the same body, every joint error
// is the retargeter's own (IK, trajectory refinement, contact enforcement), not a difference between
// skeletons, so the bound is tight: joint error p95 <= 0.5 deg and max <= 2 deg after the first 10
// frames of each motion. It is not met yet (see the assertions); the test prints the verdict and guards
// today's level.
//
// The motions are every ../shared/datasets/robot_motion/g1_*.csv (globbed, not named: the issue is also
// checked on G1 motions this folder does not hold). Each task link of the G1 robot map carries three virtual
// markers (its origin and points 0.1 m along its x and y axes) from forward kinematics of each frame. One
// zero-pose frame, standing on the floor, is prepended as the reference stance and retargeted with
// reference_time = 0, so the capture's reference is exactly the robot map's reference stance.
#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <string>
#include <vector>

#include "common/error.h"
#include "common/intermediate_file.h"
#include "common/markers_file.h"
#include "common/model.h"
#include "common/motion_file.h"
#include "common/percentile.h"
#include "common/robot_map.h"
#include "stages/export/motion_export.h"
#include "stages/retarget/retarget.h"
#include "tests/support/demo_motion.h"
#include "tests/support/independent_fk.h"
#include "tests/support/shared_data.h"
#include "tests/support/standing_pose.h"

namespace syn {
namespace {

namespace fs = std::filesystem;

constexpr double kRate = 30.0;         // the robot CSVs' frame rate
constexpr double kAxisLength = 0.1;    // m: the virtual axis markers' distance from the link origin
constexpr int64_t kSkippedFrames = 10;  // of the motion: the IK reaches the first CSV pose from the zero pose
constexpr double kDeg = 180.0 / M_PI;

int IndexOf(const std::vector<std::string>& names, const std::string& name) {
  const auto found = std::find(names.begin(), names.end(), name);
  return found == names.end() ? -1 : static_cast<int>(found - names.begin());
}

// Every g1_*.csv of the shared robot motions, sorted (stable output order).
std::vector<fs::path> G1Motions() {
  std::vector<fs::path> files;
  for (const fs::directory_entry& entry : fs::directory_iterator(testing::SharedPath("robot_motion"))) {
    const std::string name = entry.path().filename().string();
    if (entry.is_regular_file() && name.rfind("g1_", 0) == 0 && entry.path().extension() == ".csv") {
      files.push_back(entry.path());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

// The marker-set TOML of the virtual markers: each landmark's origin on its link's origin, its x and y axes
// along the link's (so the landmark frame is the link frame).
std::string VirtualMarkerSet(const RobotMap& map) {
  std::string text = "name = \"g1-virtual\"\ndescription = \"virtual markers on the G1's task links (round-trip test)\"\n";
  for (const RobotTask& task : map.tasks) {
    const std::string& l = task.landmark;
    text += "\n[[landmark]]\nname = \"" + l + "\"\norigin = [\"" + l + "_o\"]\nprimary = \"x\"\n";
    text += "x = { from = [\"" + l + "_o\"], to = [\"" + l + "_x\"] }\n";
    text += "y = { from = [\"" + l + "_o\"], to = [\"" + l + "_y\"] }\n";
  }
  return text;
}

// Markers of every frame `q[t]`: per task, the link origin and the points kAxisLength along its x and y axes.
MarkerData VirtualMarkers(const Model& model, const RobotMap& map, const std::vector<Eigen::VectorXd>& frames) {
  MarkerData data;
  data.rate_hz = kRate;
  data.up_axis = 'z';
  for (const RobotTask& task : map.tasks) {
    for (const char* suffix : {"_o", "_x", "_y"}) data.labels.push_back(task.landmark + suffix);
  }
  Workspace workspace(model);
  for (size_t t = 0; t < frames.size(); ++t) {
    data.time_s.push_back(static_cast<double>(t) / kRate);
    workspace.setQ(frames[t]);
    for (const RobotTask& task : map.tasks) {
      const Eigen::Isometry3d pose = workspace.findLinkPose(model.findLinkIndex(task.link));
      for (const Eigen::Vector3d& point :
           {Eigen::Vector3d(pose.translation()), Eigen::Vector3d(pose * (kAxisLength * Eigen::Vector3d::UnitX())),
            Eigen::Vector3d(pose * (kAxisLength * Eigen::Vector3d::UnitY()))}) {
        data.points.insert(data.points.end(), {point.x(), point.y(), point.z()});
      }
    }
  }
  return data;
}

struct JointErrors {
  double median = 0, p95 = 0, max = 0;  // deg, over every joint of every compared frame
  std::string worst_joint;
  int64_t worst_frame = -1;          // of the CSV (0-based; its line is worst_frame + 1)
  double skipped_max = 0;            // deg: the largest error in the skipped first frames
  int64_t frames_over_half_degree = 0, compared_frames = 0;
  std::vector<std::pair<double, std::string>> joint_max;  // per joint, largest first
  double base_position_max = 0;      // m, compared frames (reported, not checked)
};

// `motion` frame t + 1 against CSV frame t, joint by joint by coordinate name (the base is not compared).
JointErrors Compare(const MotionData& csv, const MotionData& motion) {
  JointErrors errors;
  const int64_t csv_nq = csv.nq(), nq = motion.nq();
  std::vector<double> all;
  std::vector<double> per_joint_max;
  std::vector<std::string> joint_names;
  std::vector<std::pair<int, int>> columns;  // (csv index, motion index)
  for (int i = 0; i < static_cast<int>(csv_nq); ++i) {
    const std::string& name = csv.coordinate_names[static_cast<size_t>(i)];
    if (name.rfind("base_", 0) == 0) continue;
    const int j = IndexOf(motion.coordinate_names, name);
    EXPECT_GE(j, 0) << "the retargeted motion has no coordinate " << name;
    if (j < 0) continue;
    columns.emplace_back(i, j);
    joint_names.push_back(name);
  }
  per_joint_max.assign(columns.size(), 0.0);
  const int bx = IndexOf(csv.coordinate_names, "base_x"), mbx = IndexOf(motion.coordinate_names, "base_x");
  for (int64_t t = 0; t < csv.frames(); ++t) {
    const double* want = &csv.q[static_cast<size_t>(t * csv_nq)];
    const double* got = &motion.q[static_cast<size_t>((t + 1) * nq)];
    double frame_max = 0;
    for (size_t c = 0; c < columns.size(); ++c) {
      const double error = std::abs(got[columns[c].second] - want[columns[c].first]) * kDeg;
      if (t < kSkippedFrames) {
        errors.skipped_max = std::max(errors.skipped_max, error);
        continue;
      }
      all.push_back(error);
      frame_max = std::max(frame_max, error);
      per_joint_max[c] = std::max(per_joint_max[c], error);
      if (error > errors.max) errors.max = error, errors.worst_joint = joint_names[c], errors.worst_frame = t;
    }
    if (t < kSkippedFrames) continue;
    ++errors.compared_frames;
    if (frame_max > 0.5) ++errors.frames_over_half_degree;
    errors.base_position_max =
        std::max(errors.base_position_max, (Eigen::Map<const Eigen::Vector3d>(got + mbx) - Eigen::Map<const Eigen::Vector3d>(want + bx)).norm());
  }
  errors.median = NearestRankPercentile(all, 0.5);
  errors.p95 = NearestRankPercentile(all, 0.95);
  for (size_t c = 0; c < columns.size(); ++c) errors.joint_max.emplace_back(per_joint_max[c], joint_names[c]);
  std::sort(errors.joint_max.rbegin(), errors.joint_max.rend());
  return errors;
}

// The test's scratch folder, removed however the test ends (an ASSERT returns early).
struct ScratchDir {
  fs::path path = fs::temp_directory_path() / ("syn_round_trip_" + std::to_string(::getpid()));
  ScratchDir() { fs::create_directories(path); }
  ~ScratchDir() { fs::remove_all(path); }
};

std::string Describe(const JointErrors& e) {
  char text[512];
  std::snprintf(text, sizeof text,
                "joint error median %.3f deg, p95 %.3f deg, max %.3f deg (%s, CSV frame %lld = line %lld, t = %.2f s); "
                "frames with a joint > 0.5 deg: %lld of %lld; first %lld frames (skipped) max %.2f deg; "
                "base position max %.1f mm",
                e.median, e.p95, e.max, e.worst_joint.c_str(), static_cast<long long>(e.worst_frame),
                static_cast<long long>(e.worst_frame + 1), static_cast<double>(e.worst_frame) / kRate,
                static_cast<long long>(e.frames_over_half_degree), static_cast<long long>(e.compared_frames),
                static_cast<long long>(kSkippedFrames), e.skipped_max, 1000 * e.base_position_max);
  std::string out = text;
  out += "; largest per joint:";
  for (size_t i = 0; i < std::min<size_t>(5, e.joint_max.size()); ++i) {
    std::snprintf(text, sizeof text, " %s %.2f", e.joint_max[i].second.c_str(), e.joint_max[i].first);
    out += text;
  }
  return out;
}

// The virtual markers of `frames` (frame 0 the reference stance) written as a markers file at `path`.
void WriteVirtualMarkers(const Model& model, const RobotMap& map, const std::vector<Eigen::VectorXd>& frames,
                         const std::string& path) {
  IntermediateWriter writer(path, {kMarkersSchema, kMarkersSchemaVersion, "test", {}, nlohmann::json::array()});
  WriteMarkerData(writer, VirtualMarkers(model, map, frames));
  writer.commit();
}

// Retargeting virtual markers back onto the G1 with reference_time = 0 (the prepended zero pose).
RetargetOptions VirtualMarkerOptions(const std::string& urdf, const std::string& map_path, const std::string& markerset,
                                     bool enforce) {
  RetargetOptions options;
  options.model = urdf;
  options.robot_map = map_path;
  options.markerset = markerset;
  options.reference_time = 0;
  options.enforce_contacts = enforce;
  return options;
}

TEST(RetargetSameRobotRoundTrip, EveryG1MotionComesBackToItsJointAngles) {
  SYN_REQUIRE_SHARED("robot_motion");
  const std::vector<fs::path> motions = G1Motions();
  ASSERT_FALSE(motions.empty()) << "no g1_*.csv in " << testing::SharedPath("robot_motion");

  const std::string urdf = testing::SourcePath(testing::kG1Urdf), map_path = testing::SourcePath(testing::kG1Map);
  const RobotMap map = LoadRobotMap(map_path);
  ASSERT_EQ(map.floating_base, "free");
  const Model model = LoadModel(urdf, map.floating_base);
  // The CSV's joint columns are the URDF's revolute joints in file order (read from the URDF text here);
  // ReadRobotCsv maps them through the model's joints, which must be the same list.
  std::vector<std::string> model_joints;
  for (const ModelJoint& joint : model.joints()) {
    if (joint.q_index >= 0 && joint.type != "free") model_joints.push_back(joint.name);
  }
  ASSERT_EQ(model_joints, testing::IndependentFk(urdf).revoluteJointsInFileOrder());
  ASSERT_EQ(model_joints.size(), 29u);

  const ScratchDir scratch;
  const fs::path& dir = scratch.path;
  const std::string markerset = (dir / "g1-virtual.toml").string();
  std::ofstream(markerset) << VirtualMarkerSet(map);
  const Eigen::VectorXd reference = testing::StandingZeroPose(model, map);

  for (const fs::path& file : motions) {
    SCOPED_TRACE(file.string());
    const std::string stem = file.stem().string();
    MotionData csv;
    try {
      csv = ReadRobotCsv(file.string(), model, kRate);  // DataError names file:line for a malformed row
    } catch (const DataError& error) {
      ADD_FAILURE() << "malformed robot CSV: " << error.what();
      continue;
    }
    std::vector<Eigen::VectorXd> frames = {reference};
    bool finite = true;
    for (int64_t t = 0; t < csv.frames() && finite; ++t) {
      frames.push_back(Eigen::Map<const Eigen::VectorXd>(&csv.q[static_cast<size_t>(t * csv.nq())], csv.nq()));
      finite = frames.back().allFinite();
      EXPECT_TRUE(finite) << file.string() << ":" << t + 1 << ": a value is not finite";
    }
    if (!finite) continue;
    if (csv.frames() <= kSkippedFrames + 1) {
      ADD_FAILURE() << file.string() << ": " << csv.frames() << " frames, too short to compare after the first "
                    << kSkippedFrames;
      continue;
    }

    const std::string markers = (dir / (stem + ".markers.h5")).string();
    WriteVirtualMarkers(model, map, frames, markers);

    for (const bool enforce : {true, false}) {
      SCOPED_TRACE(enforce ? "enforce_contacts = true (default)" : "enforce_contacts = false");
      const RetargetOptions options = VirtualMarkerOptions(urdf, map_path, markerset, enforce);
      RetargetSummary summary;
      MotionData motion;
      const auto start = std::chrono::steady_clock::now();
      try {
        motion = RetargetFile(markers, options, &summary);
      } catch (const std::exception& error) {
        ADD_FAILURE() << "retargeting failed: " << error.what();
        continue;
      }
      const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
      ASSERT_EQ(motion.frames(), csv.frames() + 1);
      EXPECT_EQ(summary.reference_frame, 0);  // the prepended zero pose, as reference_time = 0 asks
      const JointErrors errors = Compare(csv, motion);
      std::cout << stem << (enforce ? " [enforce_contacts]   " : " [no enforcement]    ") << Describe(errors)
                << "\n    scale " << summary.scale << ", heading " << summary.heading_rad * kDeg << " deg, " << seconds
                << " s; " << summary.BriefReport() << "\n";
      const std::string key = stem + (enforce ? "" : "_no_enforcement");
      RecordProperty(key + "_median_deg", std::to_string(errors.median));
      RecordProperty(key + "_p95_deg", std::to_string(errors.p95));
      RecordProperty(key + "_max_deg", std::to_string(errors.max));
      RecordProperty(key + "_worst", errors.worst_joint + " frame " + std::to_string(errors.worst_frame));
      // Issue 17's bound (p95 <= 0.5 deg, max <= 2 deg):
      //  - without enforcement (2026-11-27, session 28): walk 0.008/0.38, dance 0.015/0.78, jumping jack
      //    0.33/4.1 deg; all three meet the p95, the jumping jack not the max. Its source puts both ankles' roll
      //    up to 1° past the URDF's limit (CSV frames 16-26 and 77-81), so no G1 pose meets those frames' feet;
      //    the IK spreads the few-mm foot error up the body, and the raised arms, near the shoulder's gimbal
      //    (roll about 115°, the pitch and yaw axes nearly in line, the elbow passing through straight), turn
      //    a sub-millimetre change at the shoulder into degrees of pitch against yaw: CSV frame 77's left
      //    shoulder 4.1° off with its hand 0.5 mm and forearm 0.4° off. Before the smoothing weights were scaled
      //    per joint by the errors of that joint's own tasks (FrameIk::regularisationScales), the feet's error
      //    kept the whole body's acceleration term up and it held that arm 17° off for 10 frames: 0.90/16.8.
      //    (Smoothing weights at full strength whatever the error, before 2026-11-26: knees near straight
      //    lagged their targets, p95 2.0-10.6, max 28-37 deg.)
      //  - with it (the default; median 0.001-0.04, p95 6.7-10.3, max 24-43 deg): the Kimodo motions' own
      //    planted soles slide 13-39 mm a phase, tilt 3-5° (median) and up to 34°, and dip up to 38 mm into the
      //    floor, so exact contacts must bend their legs. A motion that keeps its contacts: next test.
      // The verdict is printed; what is asserted is a little above today's level, so nothing gets worse
      // unnoticed. Without enforcement the landmarks themselves are asserted exact: whatever joint error is
      // left is then in directions the targets cannot see.
      const bool met = errors.p95 <= 0.5 && errors.max <= 2.0;
      std::cout << "    issue 17 round-trip bound (p95 <= 0.5, max <= 2 deg): " << (met ? "met" : "NOT met") << "\n";
      EXPECT_LE(errors.median, enforce ? 0.5 : 0.05) << stem << ": joint error median (deg)";
      EXPECT_LE(errors.p95, enforce ? 14.0 : 0.5) << stem << ": joint error p95 (deg); figures printed above";
      // 2026-11-27 (session 23): a contact phase the recording's last frame cuts is now kept (the dance's left
      // foot, frames 148-150); the swing before it changed, and the dance's knee snap (frame 107, below) holds
      // the knee straight one frame longer: max 42.7 -> 55.9° with enforcement.
      EXPECT_LE(errors.max, enforce ? 60.0 : 6.0) << stem << ": joint error max (deg), " << errors.worst_joint
                                                   << " at CSV frame " << errors.worst_frame;
      if (!enforce) {
        EXPECT_LE(summary.median_position_error[0], 1e-4) << stem << ": priority-1 landmark error median (m)";
        EXPECT_LE(summary.p95_position_error[0], 0.005) << stem << ": priority-1 landmark error p95 (m)";
        EXPECT_LE(summary.p95_angle_error[0], 0.2 / kDeg) << stem << ": priority-1 landmark angle error p95 (rad)";
      }
    }
  }
}

// The Kimodo motions break the contacts they are asked to keep (their planted soles slide 13-39 mm a phase,
// tilt up to 34° and dip up to 38 mm into the floor), so their round trip above measures what the contacts
// must change as much as what the retargeter gets wrong. Here the source is a G1 motion that keeps them: each
// Kimodo motion as the stage retargets it with its contacts enforced (soles flat and still, none in the
// floor), round-tripped again, with and without enforcement.
TEST(RetargetSameRobotRoundTrip, AMotionThatKeepsItsContactsComesBackToItsJointAngles) {
  SYN_REQUIRE_SHARED("robot_motion");
  const std::vector<fs::path> motions = G1Motions();
  ASSERT_FALSE(motions.empty()) << "no g1_*.csv in " << testing::SharedPath("robot_motion");
  const std::string urdf = testing::SourcePath(testing::kG1Urdf), map_path = testing::SourcePath(testing::kG1Map);
  const RobotMap map = LoadRobotMap(map_path);
  const Model model = LoadModel(urdf, map.floating_base);
  const ScratchDir scratch;
  const std::string markerset = (scratch.path / "g1-virtual.toml").string();
  std::ofstream(markerset) << VirtualMarkerSet(map);
  const Eigen::VectorXd reference = testing::StandingZeroPose(model, map);
  const int64_t nq = model.nq();
  for (const fs::path& file : motions) {
    SCOPED_TRACE(file.string());
    const std::string stem = file.stem().string();
    const MotionData csv = ReadRobotCsv(file.string(), model, kRate);
    std::vector<Eigen::VectorXd> frames = {reference};
    for (int64_t t = 0; t < csv.frames(); ++t) frames.push_back(Eigen::Map<const Eigen::VectorXd>(&csv.q[static_cast<size_t>(t * nq)], nq));
    const std::string markers = (scratch.path / (stem + ".markers.h5")).string();
    WriteVirtualMarkers(model, map, frames, markers);
    RetargetSummary kept;
    const MotionData enforced = RetargetFile(markers, VirtualMarkerOptions(urdf, map_path, markerset, true), &kept);
    ASSERT_EQ(enforced.nq(), nq);
    // Still but for the roll at a phase's ends, which moves the sole centre with it (G1's max_roll; the
    // dance's left plant at frames 24-34 rolls 8 mm off its toe edge, the other phases <= 5 mm): at most the
    // issue's median drift bound.
    EXPECT_LE(kept.max_drift, 0.010) << stem << ": the enforced motion's planted soles are still (m)";
    EXPECT_LE(kept.deepest_penetration, 0.005) << stem << ": and out of the floor (m)";
    // The contact-keeping source: the enforced motion without its first frame (the prepended reference).
    MotionData source;
    source.coordinate_names = enforced.coordinate_names;
    source.time_s.assign(enforced.time_s.begin() + 1, enforced.time_s.end());
    source.q.assign(enforced.q.begin() + nq, enforced.q.end());
    frames = {reference};
    for (int64_t t = 0; t < source.frames(); ++t) frames.push_back(Eigen::Map<const Eigen::VectorXd>(&source.q[static_cast<size_t>(t * nq)], nq));
    const std::string kept_markers = (scratch.path / (stem + ".kept.markers.h5")).string();
    WriteVirtualMarkers(model, map, frames, kept_markers);
    JointErrors errors[2];
    for (const bool enforce : {true, false}) {
      const MotionData back = RetargetFile(kept_markers, VirtualMarkerOptions(urdf, map_path, markerset, enforce), nullptr);
      ASSERT_EQ(back.frames(), source.frames() + 1);
      errors[enforce] = Compare(source, back);
      std::cout << stem << " keeping its contacts" << (enforce ? " [enforce_contacts]   " : " [no enforcement]    ")
                << Describe(errors[enforce]) << "\n";
    }
    // Measured 2026-11-26, median/p95/max deg with enforcement (without): walk 0.001/0.015/0.60
    // (0.001/0.019/1.85), dance 0.002/0.92/26.3 (0.001/0.021/10.6), jumping jack 0.006/3.2/17.5
    // (0.002/0.19/9.7). With enforcement the walk meets the bound; the dance and the jumping jack do
    // not, because the enforcement is not idempotent: on a motion it has already made contact-exact it still
    // lowers the base (jumping jack: up to 9 mm in 103 frames) and moves the pelvis for plants (53 frames,
    // up to 36 mm) where a phase begins or ends on a foot rolled onto its sole edge. The worst joints of
    // both runs are knees within a few degrees of straight, which the feet barely see.
    // 2026-11-27, a plant moved to where its foot touched down now keeps its own pitch (flat, or rolled with
    // the source near the phase's ends) instead of carrying the touchdown's tilt over the whole phase: walk
    // 0.001/0.016/0.53 (0.001/0.019/1.48), dance 0.002/0.87/13.1 (0.001/0.099/38.2), jumping jack
    // 0.006/3.6/23.0 (0.002/0.23/11.5). The dance's 38° is one frame: its first pass straightens the left knee
    // at a phase's end while the pelvis rises (CMU-style toe-off beyond G1's roll) and releases it 0 -> 38° in
    // one 30 Hz frame, which the IK follows a frame late.
    for (const bool enforce : {true, false}) {
      const bool met = errors[enforce].p95 <= 0.5 && errors[enforce].max <= 2.0;
      std::cout << "    issue 17 round-trip bound (p95 <= 0.5, max <= 2 deg)" << (enforce ? " with enforcement: " : " without: ")
                << (met ? "met" : "NOT met") << "\n";
      EXPECT_LE(errors[enforce].median, 0.05) << stem << (enforce ? " [enforce_contacts]" : " [no enforcement]");
      EXPECT_LE(errors[enforce].p95, enforce ? 4.0 : 0.5) << stem << (enforce ? " [enforce_contacts]" : " [no enforcement]");
      // Session 23: the dance's knee snap one frame longer with the kept end phase (see the test above):
      // with enforcement 13.1 -> 38.2°.
      EXPECT_LE(errors[enforce].max, 40.0) << stem << (enforce ? " [enforce_contacts]" : " [no enforcement]");
    }
  }
}

}  // namespace
}  // namespace syn
