// Per-chain proportions (--proportions chains, stance_alignment.h): the scales the stage reports and the
// targets it tracks, against an independent computation from the capture's own skeleton joints and a URDF
// forward kinematics that shares no code with the stage. CMU walk 02_01 (bundled) onto the G1.
#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <map>
#include <string>
#include <utility>
#include <vector>

#include "common/intermediate_file.h"
#include "common/markers_file.h"
#include "stages/ingest/ingest.h"
#include "stages/retarget/retarget.h"
#include "tests/support/demo_motion.h"
#include "tests/support/independent_fk.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

// The position in frame t of `name` from per-frame rows of `stride` doubles per name, position first.
Eigen::Vector3d Position(const std::vector<std::string>& names, const std::vector<double>& rows, size_t stride,
                         const std::string& name, int64_t frame) {
  const auto found = std::find(names.begin(), names.end(), name);
  EXPECT_NE(found, names.end()) << name;
  const double* row = &rows[(static_cast<size_t>(frame) * names.size() + static_cast<size_t>(found - names.begin())) * stride];
  return {row[0], row[1], row[2]};
}

Eigen::Vector3d Joint(const MarkerData& capture, const std::string& body, int64_t frame) {
  return Position(capture.bodies, capture.body_pose, 7, body, frame);
}

Eigen::Vector3d Target(const MotionData& motion, const std::string& landmark, int64_t frame) {
  return Position(motion.landmark_names, motion.landmark_targets, 7, landmark, frame);
}

class Proportions : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() / ("syn_proportions_" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
    IngestOptions ingest;
    ingest.drop_first_frame = true;
    capture_ = IngestCapture(testing::SourcePath("datasets/demo/02_01.bvh"), ingest, nullptr);
    markers_ = (dir_ / "walk.markers.h5").string();
    IntermediateWriter writer(markers_, {kMarkersSchema, kMarkersSchemaVersion, "test", {}, nlohmann::json::array()});
    WriteMarkerData(writer, capture_);
    writer.commit();
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  RetargetOptions Options(bool per_chain) const {
    RetargetOptions options;
    options.model = testing::SourcePath(testing::kG1Urdf);
    options.robot_map = testing::SourcePath(testing::kG1Map);
    options.markerset = testing::SourcePath("manifests/markersets/cmu-bvh.toml");
    options.proportions_per_chain = per_chain;
    // The targets are checked against the capture's own axes (the demo walk's floor rises 0.95°, which the
    // stage would level: floor_levelling_test.cpp checks that).
    options.floor.enabled = false;
    return options;
  }

  std::filesystem::path dir_;
  std::string markers_;
  MarkerData capture_;
};

TEST_F(Proportions, LegsAndArmsScaleByTheirOwnLengths) {
  RetargetSummary summary;
  const MotionData motion = RetargetFile(markers_, Options(true), &summary);
  ASSERT_EQ(summary.reference_frame, 0);

  // The subject at the reference frame, from the BVH's joints: CMU's Hips, LeftUpLeg (hip), LeftLeg (knee),
  // LeftFoot (ankle), LeftArm (glenohumeral), LeftForeArm (elbow), LeftHand (wrist).
  const auto at0 = [&](const char* body) { return Joint(capture_, body, 0); };
  double subject_arm[2], subject_leg[2];
  for (int side = 0; side < 2; ++side) {
    const std::string s = side == 0 ? "Left" : "Right";
    subject_leg[side] = (at0((s + "UpLeg").c_str()) - at0((s + "Leg").c_str())).norm() +
                        (at0((s + "Leg").c_str()) - at0((s + "Foot").c_str())).norm();
    subject_arm[side] = (at0((s + "Arm").c_str()) - at0((s + "ForeArm").c_str())).norm() +
                        (at0((s + "ForeArm").c_str()) - at0((s + "Hand").c_str())).norm();
  }
  // The G1 in its zero pose, by the independent FK: hip pitch joint (the first link below the pelvis both
  // legs hang from) to the ankle link; shoulder pitch joint (the first link below the torso both arms hang
  // from) to the elbow link to the hand link.
  const testing::IndependentFk fk(testing::SourcePath(testing::kG1Urdf));
  const auto links = fk.poses(std::map<std::string, double>{}, Eigen::Isometry3d::Identity());
  const auto at = [&](const std::string& link) { return links.at(link).translation(); };
  double arm_ratio = 0, leg_ratio = 0;
  for (int side = 0; side < 2; ++side) {
    const std::string s = side == 0 ? "left" : "right";
    leg_ratio += 0.5 * (at(s + "_hip_pitch_link") - at(s + "_ankle_roll_link")).norm() / subject_leg[side];
    const double robot_arm = (at(s + "_shoulder_pitch_link") - at(s + "_elbow_link")).norm() +
                             (at(s + "_elbow_link") - at(s + "_rubber_hand")).norm();
    arm_ratio += 0.5 * robot_arm / subject_arm[side];
  }
  EXPECT_NEAR(summary.scale, leg_ratio, 1e-9);
  EXPECT_NEAR(summary.arm_scale, arm_ratio, 1e-9);
  // The G1 map's head link sits at the waist: its height ratio (the default mode's one scale) is far below
  // the leg ratio, the reason this mode exists.
  RetargetSummary height;
  (void)RetargetFile(markers_, Options(false), &height);
  EXPECT_EQ(height.scale, height.arm_scale);
  EXPECT_LT(height.scale, 0.8 * summary.scale) << "height " << height.scale << ", legs " << summary.scale;

  // Every frame's targets: the pelvis moves by the leg scale, a hand by the pelvis's motion plus its own
  // motion relative to the pelvis at the arm scale, both turned by the reported heading (targets compared
  // as displacements from frame 0, so the vertical move onto the planted soles cancels).
  const Eigen::Matrix3d turn = Eigen::AngleAxisd(-summary.heading_rad, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  double worst = 0;
  for (int64_t t = 0; t < motion.frames(); ++t) {
    const Eigen::Vector3d pelvis_move = at0("Hips") - Joint(capture_, "Hips", t);
    const Eigen::Vector3d expected_pelvis = -summary.scale * (turn * pelvis_move);
    worst = std::max(worst, (Target(motion, "pelvis", t) - Target(motion, "pelvis", 0) - expected_pelvis).norm());
    const Eigen::Vector3d relative = (Joint(capture_, "LeftHand", t) - Joint(capture_, "Hips", t)) -
                                     (at0("LeftHand") - at0("Hips"));
    const Eigen::Vector3d expected_hand = expected_pelvis + summary.arm_scale * (turn * relative);
    worst = std::max(worst, (Target(motion, "left_hand", t) - Target(motion, "left_hand", 0) - expected_hand).norm());
  }
  EXPECT_LT(worst, 1e-9) << "largest target difference, m";
}

// HRP-4C's map asks for per-chain proportions: its legs (hip to ankle, by the independent FK of its zero
// pose) against the subject's thigh and shank, not its pelvis link's height — hip_base is 0.197 m above its
// hips, CMU's Hips 0.10 m —, which gave 1.01 on this walk for a leg ratio of 0.82.
TEST_F(Proportions, Hrp4cLegsScaleByTheirLength) {
  SYN_REQUIRE_SHARED("robots/humanoid_synergies/HRP4c_optitrack_model.urdf");
  RetargetOptions options = Options(false);
  options.proportions_per_chain.reset();  // the map's
  options.model = testing::SharedPath("robots/humanoid_synergies/HRP4c_optitrack_model.urdf");
  options.robot_map = testing::SourcePath("manifests/robots/hrp4c.toml");
  RetargetSummary summary;
  (void)RetargetFile(markers_, options, &summary);
  const testing::IndependentFk fk(options.model);
  const auto links = fk.poses(std::map<std::string, double>{}, Eigen::Isometry3d::Identity());
  const auto at = [&](const std::string& link) { return links.at(link).translation(); };
  const auto at0 = [&](const std::string& body) { return Joint(capture_, body, 0); };
  double leg_ratio = 0;
  for (const auto& [robot, subject] : {std::pair<std::string, std::string>{"LL", "Left"}, {"RL", "Right"}}) {
    const double subject_leg = (at0(subject + "UpLeg") - at0(subject + "Leg")).norm() + (at0(subject + "Leg") - at0(subject + "Foot")).norm();
    leg_ratio += 0.5 * (at(robot + "_KOSY_L1") - at(robot + "_foot")).norm() / subject_leg;
  }
  EXPECT_NEAR(summary.scale, leg_ratio, 1e-9);
  EXPECT_LT(summary.scale, 0.85);
}

// The feet's neutral reference (stance_alignment.h NeutralReference): the walk's first frame is mid-stride,
// yet over the take each foot's target sits, at the median, where the robot's reference stance has it
// relative to the pelvis (the G1's zero pose, by the independent FK). Measured from the first frame
// instead, one foot stays a stride's fraction behind the pelvis and the other ahead.
TEST_F(Proportions, FeetAreMeasuredFromTheirMedianOffsetToThePelvis) {
  const testing::IndependentFk fk(testing::SourcePath(testing::kG1Urdf));
  const auto links = fk.poses(std::map<std::string, double>{}, Eigen::Isometry3d::Identity());
  auto median_offset_error = [&](const MotionData& motion, const std::string& side) {
    const Eigen::Vector3d stance = links.at(side + "_ankle_roll_link").translation() - links.at("pelvis").translation();
    std::vector<double> along, across;
    for (int64_t t = 0; t < motion.frames(); ++t) {
      const Eigen::Vector3d offset = Target(motion, side + "_foot", t) - Target(motion, "pelvis", t);
      along.push_back(offset.x()), across.push_back(offset.y());
    }
    std::sort(along.begin(), along.end());
    std::sort(across.begin(), across.end());
    const size_t middle = along.size() / 2;
    return std::hypot(along[middle] - stance.x(), across[middle] - stance.y());
  };
  RetargetOptions options = Options(false);
  const MotionData neutral = RetargetFile(markers_, options, nullptr);
  options.neutral_reference = false;
  const MotionData first_frame = RetargetFile(markers_, options, nullptr);
  double worst_first_frame = 0;
  for (const std::string side : {"left", "right"}) {
    // Within the heading's sway: the median is taken in the pelvis's heading at each frame.
    EXPECT_LT(median_offset_error(neutral, side), 0.02) << side;
    worst_first_frame = std::max(worst_first_frame, median_offset_error(first_frame, side));
  }
  EXPECT_GT(worst_first_frame, 0.05);
}

// The capture with each arm of frame `frame` raised sideways to the horizontal about its shoulder (CMU's
// LeftArm / RightArm joint), as a subject calibrating in a T-pose: every body below the shoulder turned by
// the rotation that takes its hand straight out from the other shoulder, positions and orientations.
MarkerData WithTPoseAt(const MarkerData& capture, int64_t frame) {
  MarkerData posed = capture;
  const auto index = [&](const std::string& body) {
    return static_cast<size_t>(std::find(capture.bodies.begin(), capture.bodies.end(), body) - capture.bodies.begin());
  };
  double* row = &posed.body_pose[static_cast<size_t>(frame) * capture.bodies.size() * 7];
  const auto position = [&](size_t body) { return Eigen::Vector3d(row[body * 7], row[body * 7 + 1], row[body * 7 + 2]); };
  for (const auto& [side, other] : {std::pair<std::string, std::string>{"Left", "Right"}, {"Right", "Left"}}) {
    const size_t shoulder = index(side + "Arm");
    const Eigen::Vector3d origin = position(shoulder);
    Eigen::Vector3d outward = origin - position(index(other + "Arm"));
    outward.z() = 0;
    const Eigen::Quaterniond raise = Eigen::Quaterniond::FromTwoVectors(position(index(side + "Hand")) - origin, outward);
    for (size_t body = 0; body < capture.bodies.size(); ++body) {
      bool below = false;  // the shoulder itself or a descendant of it
      for (std::string at = capture.bodies[body]; !at.empty() && !below;) {
        below = at == side + "Arm";
        const size_t parent = index(at);
        at = parent < capture.body_parents.size() ? capture.body_parents[parent] : "";
      }
      if (!below) continue;
      const Eigen::Vector3d moved = origin + raise * (position(body) - origin);
      const Eigen::Quaterniond turned = raise * Eigen::Quaterniond(row[body * 7 + 3], row[body * 7 + 4], row[body * 7 + 5], row[body * 7 + 6]);
      const double values[7] = {moved.x(), moved.y(), moved.z(), turned.w(), turned.x(), turned.y(), turned.z()};
      std::copy(values, values + 7, row + body * 7);
    }
  }
  return posed;
}

// A walk that starts in a T-pose (CMU 03_02 does): its reference frame holds the arms out, and measured from
// it every hanging hand of the walk became a displacement inwards and down, the G1's hands crossing in front
// of it. An arm raised that far above its median over the take is measured from the take's first frame at or
// below that median (stance_alignment.h NeutralReference), found here from the BVH's own shoulder (LeftArm)
// and wrist (LeftHand) joints: in that frame the hand's target sits where the G1's reference stance holds its
// hand, relative to the pelvis (the independent FK of its zero pose), in the pelvis target's axes.
TEST_F(Proportions, ArmsRaisedInTheFirstFrameAreMeasuredFromATypicalFrame) {
  const MarkerData t_pose = WithTPoseAt(capture_, 0);
  const std::string t_pose_markers = (dir_ / "t_pose.markers.h5").string();
  {
    IntermediateWriter writer(t_pose_markers, {kMarkersSchema, kMarkersSchemaVersion, "test", {}, nlohmann::json::array()});
    WriteMarkerData(writer, t_pose);
    writer.commit();
  }
  RetargetOptions options = Options(true);
  options.enforce_contacts = false;
  const MotionData from_typical = RetargetFile(t_pose_markers, options, nullptr);
  options.neutral_reference = false;
  const MotionData from_t_pose = RetargetFile(t_pose_markers, options, nullptr);
  const testing::IndependentFk fk(testing::SourcePath(testing::kG1Urdf));
  const auto links = fk.poses(std::map<std::string, double>{}, Eigen::Isometry3d::Identity());
  const int64_t frames = static_cast<int64_t>(t_pose.time_s.size());
  for (const std::string side : {"Left", "Right"}) {
    SCOPED_TRACE(side);
    std::vector<double> elevation;
    for (int64_t t = 0; t < frames; ++t) {
      const Eigen::Vector3d arm = Joint(t_pose, side + "Hand", t) - Joint(t_pose, side + "Arm", t);
      elevation.push_back(std::acos(-arm.z() / arm.norm()));
    }
    EXPECT_NEAR(elevation[0], M_PI / 2, 1e-9);  // the T-pose
    std::vector<double> sorted = elevation;
    std::sort(sorted.begin(), sorted.end());
    const double median = sorted[static_cast<size_t>(std::ceil(0.5 * static_cast<double>(frames))) - 1];  // nearest rank
    ASSERT_LT(median, M_PI / 4);  // a walker's arms hang
    const int64_t typical = std::find_if(elevation.begin(), elevation.end(), [&](double e) { return e <= median; }) - elevation.begin();
    const std::string hand = side == "Left" ? "left" : "right";
    const Eigen::Vector3d robot = links.at(hand + "_rubber_hand").translation() - links.at("pelvis").translation();
    const auto in_pelvis_axes = [&](const MotionData& motion) {
      const double* pelvis = &motion.landmark_targets[static_cast<size_t>(typical) * motion.landmark_names.size() * 7 +
                                                      static_cast<size_t>(std::find(motion.landmark_names.begin(), motion.landmark_names.end(), "pelvis") -
                                                                          motion.landmark_names.begin()) * 7];
      const Eigen::Quaterniond axes(pelvis[3], pelvis[4], pelvis[5], pelvis[6]);
      return Eigen::Vector3d(axes.conjugate() * (Target(motion, hand + "_hand", typical) - Target(motion, "pelvis", typical)));
    };
    const double off = (in_pelvis_axes(from_typical) - robot).norm(), t_posed = (in_pelvis_axes(from_t_pose) - robot).norm();
    std::cout << hand << " hand at frame " << typical << ": " << off << " m from the G1's reference hand; measured from the T-pose "
              << t_posed << " m\n";
    EXPECT_LT(off, 0.02);
    EXPECT_GT(t_posed, 0.2);
  }
}

}  // namespace
}  // namespace syn

namespace syn {
namespace {

// --scale auto measures the subject standing: in the capture's calibration frame (the T-pose syn-ingest
// --drop-first-frame keeps) when it has one. The same capture with that T-pose put first in the take and
// retargeted from it (--reference-time 0, heights at the reference frame) gives the same scale; from the
// take's first frame, which on the bundled salsa (CMU 60_10) is mid-dance, the ratio differs.
TEST_F(Proportions, TheScaleIsTheStandingCalibrationFramesHeight) {
  for (const char* file : {"datasets/demo/02_01.bvh", "datasets/demo/60_10.bvh"}) {
    SCOPED_TRACE(file);
    IngestOptions ingest;
    ingest.drop_first_frame = true;
    const MarkerData capture = IngestCapture(testing::SourcePath(file), ingest, nullptr);
    ASSERT_FALSE(capture.calibration_body_pose.empty());
    const auto write = [&](const MarkerData& data, const std::string& name) {
      const std::string path = (dir_ / name).string();
      IntermediateWriter writer(path, {kMarkersSchema, kMarkersSchemaVersion, "test", {}, nlohmann::json::array()});
      WriteMarkerData(writer, data);
      writer.commit();
      return path;
    };
    MarkerData standing_first = capture;
    std::copy(capture.calibration_body_pose.begin(), capture.calibration_body_pose.end(), standing_first.body_pose.begin());
    standing_first.calibration_body_pose.clear();
    RetargetOptions options = Options(false);
    options.smoothing = 0;
    options.enforce_contacts = false;
    RetargetSummary from_calibration, from_standing_frame, from_take_frame;
    (void)RetargetFile(write(capture, "capture.markers.h5"), options, &from_calibration);
    options.reference_time = 0;
    (void)RetargetFile(write(standing_first, "standing.markers.h5"), options, &from_standing_frame);
    (void)RetargetFile(write(capture, "capture.markers.h5"), options, &from_take_frame);
    EXPECT_NEAR(from_calibration.scale, from_standing_frame.scale, 1e-12);
    EXPECT_GT(std::abs(from_take_frame.scale - from_calibration.scale), 0.005);
    std::cout << file << ": scale " << from_calibration.scale << " standing, " << from_take_frame.scale
              << " from the take's first frame\n";
  }
}

}  // namespace
}  // namespace syn
