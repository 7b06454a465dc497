// Every real capture we have, retargeted onto G1 and HRP-4C with the stage's
// defaults: the CMU BVH archive (all three naming conventions), the CMU, HDM05
// and OptiTrack Motive C3D trials, and the HumanML3D joints. For each run it
// asserts no NaN, no joint-limit violation, continuity (no joint moves more per
// frame than its URDF velocity limit allows) and that priority-1 landmarks are
// tracked better than priority-2 ones; and it prints the per-priority error
// table. It is the slowest test (minutes in Release); the sanitizer build skips it, since the code
// it runs is the same the other retarget tests run under the sanitizers.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <set>
#include <string>
#include <unistd.h>
#include <vector>

#include <Eigen/Geometry>

#include "common/intermediate_file.h"
#include "common/markers_file.h"
#include "common/model.h"
#include "common/robot_map.h"
#include "stages/ingest/ingest.h"
#include "stages/retarget/retarget.h"
#include "stages/retarget/speed_bound.h"
#include "tests/support/demo_motion.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

struct Capture {
  std::string path;       // under ../shared/datasets
  std::string markerset;  // manifests/markersets/NAME.toml
  IngestOptions ingest;
};

struct Robot {
  std::string name, urdf, map;
  // Priority-1 landmark position error bounds per capture, mm (median, p95): the worst capture of the sweep
  // with the defaults, plus a margin (measured values at the SweepOnto calls below).
  double max_p1_median_mm = 0, max_p1_p95_mm = 0;
};

std::vector<Capture> RealCaptures() {
  std::vector<Capture> captures;
  const std::filesystem::path bvh_root = testing::SharedPath("cmu_bvh");
  std::vector<std::string> bvh;
  for (const auto& entry : std::filesystem::recursive_directory_iterator(bvh_root)) {
    if (entry.path().extension() == ".bvh") bvh.push_back(entry.path().string());
  }
  std::sort(bvh.begin(), bvh.end());
  for (const std::string& path : bvh) {
    Capture capture{path, "cmu-bvh", {}};
    // cgspeed's MotionBuilder and Daz conversions start with a reference pose; the 3dsMax excerpt does not.
    capture.ingest.drop_first_frame = path.find("_excerpt") == std::string::npos;
    captures.push_back(capture);
  }
  // (walkingOptiTrack.c3d, the other Motive file, has leg markers only: see LegOnlyCaptureFails… below.)
  for (const char* c3d : {"c3d/cmu/85_02.c3d", "c3d/cmu/85_12.c3d", "c3d/hdm05/HDM_bd_05-01_01_120.c3d",
                          "c3d/optitrack_motive/kinematics_tennis_serve.c3d"}) {
    Capture capture{testing::SharedPath(c3d), "plugin-gait", {}};
    capture.ingest.fill_gaps = 30;
    captures.push_back(capture);
  }
  captures.push_back({testing::SharedPath("humanml3d/new_joints_012314.npy"), "humanml3d22", {}});
  return captures;
}

constexpr double kMaxJointSpeed = 80.0;  // rad/s
constexpr double kMaxBaseSpeed = 30.0;   // m/s

void SweepOnto(const Robot& robot) {
  const std::vector<Robot> robots = {robot};
  const std::string dir = std::filesystem::temp_directory_path() / ("syn_sweep_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::fprintf(stderr, "%-44s %-7s %6s  %-21s %-23s %-23s %s\n", "capture", "robot", "frames", "P1 pos median/p95 mm",
               "P1 angle median/p95 deg", "P2 angle median/p95 deg", "worst joint step");
  int runs = 0;
  for (const Capture& capture : RealCaptures()) {
    if (!std::filesystem::exists(capture.path)) {
      std::fprintf(stderr, "skipped (absent): %s\n", capture.path.c_str());
      continue;
    }
    const std::string markers = dir + "/capture.markers.h5";
    {
      IntermediateWriter writer(markers, {kMarkersSchema, kMarkersSchemaVersion, "test", {}, nlohmann::json::array()});
      WriteMarkerData(writer, IngestCapture(capture.path, capture.ingest, nullptr));
      writer.commit();
    }
    const std::string name = std::filesystem::path(capture.path).filename().string();
    for (const Robot& robot : robots) {
      SCOPED_TRACE(name + " onto " + robot.name);
      RetargetOptions options;
      options.model = robot.urdf;
      options.robot_map = robot.map;
      options.markerset = testing::SourcePath("manifests/markersets/" + capture.markerset + ".toml");
      RetargetSummary summary;
      const MotionData motion = RetargetFile(markers, options, &summary);
      const Model model = Model::Load(robot.urdf);
      const double speed_scale = LoadRobotMap(robot.map).velocity_limit_scale;  // what the stage bounds steps by
      ++runs;

      const int64_t nq = motion.nq(), frames = motion.frames();
      const int first_joint = model.hasFreeBase() ? 7 : 0;
      std::set<int> prismatic_coordinates;
      std::vector<int> virtual_turns;  // a virtual base chain's x, y, z revolute coordinates (HRP-4C's)
      for (const ModelJoint& joint : model.joints()) {
        if (joint.type == "prismatic") prismatic_coordinates.insert(joint.q_index);
        if (joint.type == "revolute" && joint.u_index >= 0 && !model.actuatedVelocities()[static_cast<size_t>(joint.u_index)]) {
          virtual_turns.push_back(joint.q_index);
        }
      }
      // Their orientation Rx Ry Rz at frame t: near a pitch of ±90° the three angles themselves may swing by
      // much more than the orientation turns, so the base's continuity is that orientation's.
      const auto base_rotation = [&](int64_t t) {
        const double* row = &motion.q[static_cast<size_t>(t * nq)];
        return Eigen::Matrix3d(Eigen::AngleAxisd(row[virtual_turns[0]], Eigen::Vector3d::UnitX()) *
                               Eigen::AngleAxisd(row[virtual_turns[1]], Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(row[virtual_turns[2]], Eigen::Vector3d::UnitZ()));
      };
      bool finite = true, within_limits = true, continuous = true;
      std::string where;
      for (int64_t t = 0; t < frames; ++t) {
        const double dt = t > 0 ? motion.time_s[static_cast<size_t>(t)] - motion.time_s[static_cast<size_t>(t - 1)] : 0.0;
        for (int64_t i = 0; i < nq; ++i) {
          const double q = motion.q[static_cast<size_t>(t * nq + i)];
          finite = finite && std::isfinite(q);
          if (i < first_joint) continue;
          const double lower = model.qLower()[i], upper = model.qUpper()[i];
          if (q < lower - 1e-9 || q > upper + 1e-9) {
            within_limits = false;
            where = motion.coordinate_names[static_cast<size_t>(i)] + " frame " + std::to_string(t);
          }
          const bool virtual_turn = std::find(virtual_turns.begin(), virtual_turns.end(), static_cast<int>(i)) != virtual_turns.end();
          if (t > 0 && !virtual_turn) {
            // Continuity: each joint moves at most its URDF velocity limit × dt per frame, times the robot
            // map's velocity_limit_scale up to speed_bound.h's cap (the IK and the refinement both keep that
            // bound; HRP-4C's map allows 4 times its URDF speeds); a coordinate with no real limit (a virtual base's 1000 rad/s)
            // at most kMaxJointSpeed, or kMaxBaseSpeed if prismatic. A flip between IK branches (about π in
            // one frame) is far above either.
            const double step = std::abs(q - motion.q[static_cast<size_t>((t - 1) * nq + i)]);
            const bool prismatic = prismatic_coordinates.count(static_cast<int>(i)) > 0;
            const double urdf_speed = model.uLimit()[i - (model.hasFreeBase() ? 1 : 0)];
            const double speed = std::min(speed_scale * SpeedPerScaledSecond(urdf_speed, speed_scale),
                                          prismatic ? kMaxBaseSpeed : kMaxJointSpeed);
            const double bound = speed * dt + 1e-9;
            if (step > bound) {
              continuous = false;
              where = motion.coordinate_names[static_cast<size_t>(i)] + " frame " + std::to_string(t) + ": step " +
                      std::to_string(step) + ", bound " + std::to_string(bound);
            }
          }
        }
      }
      for (int64_t t = 1; t < frames && virtual_turns.size() == 3; ++t) {
        const double dt = motion.time_s[static_cast<size_t>(t)] - motion.time_s[static_cast<size_t>(t - 1)];
        const double turn = Eigen::AngleAxisd(base_rotation(t) * base_rotation(t - 1).transpose()).angle();
        if (turn > kMaxJointSpeed * dt + 1e-9) {
          continuous = false;
          where = "the virtual base's orientation, frame " + std::to_string(t) + ": turned " + std::to_string(turn) + " rad";
        }
      }
      for (double value : motion.u) finite = finite && std::isfinite(value);
      for (double value : motion.tau) finite = finite && std::isfinite(value);
      EXPECT_TRUE(finite);
      EXPECT_TRUE(within_limits) << where;
      EXPECT_TRUE(continuous) << where;
      // Priority 1 (pelvis, feet, hands, head) against priority 2 (upper torso, elbows): both are tracked as
      // orientations, so compare angles.
      if (std::isfinite(summary.median_angle_error[1])) {
        EXPECT_LT(summary.median_angle_error[0], summary.median_angle_error[1]);
      }
      EXPECT_LT(1000 * summary.median_position_error[0], robot.max_p1_median_mm) << "priority-1 median error, mm";
      EXPECT_LT(1000 * summary.p95_position_error[0], robot.max_p1_p95_mm) << "priority-1 p95 error, mm";
      const double deg = 180.0 / M_PI;
      std::fprintf(stderr, "%-44s %-7s %6lld  %8.1f / %-10.1f %8.2f / %-12.2f %8.2f / %-12.2f %.3f rad (%s)\n",
                   name.c_str(), robot.name.c_str(), static_cast<long long>(frames),
                   1000 * summary.median_position_error[0], 1000 * summary.p95_position_error[0],
                   deg * summary.median_angle_error[0], deg * summary.p95_angle_error[0],
                   deg * summary.median_angle_error[1], deg * summary.p95_angle_error[1], summary.worst_joint_step,
                   summary.worst_joint_step_name.c_str());
    }
  }
  std::filesystem::remove_all(dir);
  EXPECT_EQ(runs, 56);  // 51 BVH + 4 full-body C3D + 1 HumanML3D captures
}

TEST(RetargetRealData, EveryCaptureOntoG1) {
#ifdef SYN_SANITIZED_BUILD
  GTEST_SKIP() << "the real-data retarget sweep runs in the Release test run, not under the sanitizers";
#endif
  SYN_REQUIRE_SHARED("cmu_bvh/index.csv");
  // Measured (build/bin/test_retarget --gtest_filter=RetargetRealData.EveryCaptureOntoG1, 2026-11-24, contacts
  // enforced and the heading from the pelvis, both default since): the median of the captures' P1 medians is
  // 44 mm (43 before); the worst median 131 mm (09_11.bvh, a run: 102 before, on 08_07), the worst p95 400 mm
  // (08_07, 328 before). Contacts rank above the P1 tasks: planted feet stay where the stance began and the
  // pelvis comes down where a bent stance knee needs it, so running captures track their P1 targets less well.
  SweepOnto({"G1", testing::SourcePath(testing::kG1Urdf), testing::SourcePath(testing::kG1Map), 150.0, 450.0});
}

TEST(RetargetRealData, EveryCaptureOntoHrp4c) {
#ifdef SYN_SANITIZED_BUILD
  GTEST_SKIP() << "the real-data retarget sweep runs in the Release test run, not under the sanitizers";
#endif
  SYN_REQUIRE_SHARED("cmu_bvh/index.csv");
  SYN_REQUIRE_SHARED("robots/humanoid_synergies/HRP4c_optitrack_model.urdf");
  // Measured as for the G1: worst median 320 mm (08_07.bvh; 09_01 319), worst p95 669 mm (08_07); with the
  // feet's heading and no contact enforcement they were 269 and 581. These are today's HRP-4C numbers, far
  // worse than the G1's (its map's single scale puts running strides beyond its legs, issue 17 item 3): the
  // bound stops them getting worse and is to be tightened when the retargeter tracks HRP-4C as well as the G1.
  SweepOnto({"HRP-4C", testing::SharedPath("robots/humanoid_synergies/HRP4c_optitrack_model.urdf"),
             testing::SourcePath("manifests/robots/hrp4c.toml"), 360.0, 750.0});
}

// OptiTrack's older leg-only export (12 Foot/Knee/Leg markers) cannot drive a whole humanoid: the stage
// must say which marker it needs and list the labels the file has.
TEST(RetargetRealData, LegOnlyCaptureFailsWithTheLabelsItHas) {
  SYN_REQUIRE_SHARED("c3d/optitrack_motive/walkingOptiTrack.c3d");
  const std::string dir = std::filesystem::temp_directory_path() / ("syn_legs_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string markers = dir + "/legs.markers.h5";
  {
    IntermediateWriter writer(markers, {kMarkersSchema, kMarkersSchemaVersion, "test", {}, nlohmann::json::array()});
    WriteMarkerData(writer, IngestCapture(testing::SharedPath("c3d/optitrack_motive/walkingOptiTrack.c3d"), {}, nullptr));
    writer.commit();
  }
  RetargetOptions options;
  options.model = testing::SourcePath(testing::kG1Urdf);
  options.robot_map = testing::SourcePath(testing::kG1Map);
  options.markerset = testing::SourcePath("manifests/markersets/plugin-gait.toml");
  try {
    (void)RetargetFile(markers, options, nullptr);
    ADD_FAILURE() << "a leg-only capture was retargeted";
  } catch (const std::exception& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("plugin-gait.toml:"), std::string::npos) << message;
    EXPECT_NE(message.find("Knee_Marker1"), std::string::npos) << message;
  }
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace syn
