// foot_yaw_range.h: the turn about the vertical each leg gives its foot, against the joint limits read
// independently from the URDF text (and the robot map's [joint_ranges]), and foot targets held within it
// with their tilt kept.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <tuple>
#include <utility>

#include "common/model.h"
#include "common/robot_map.h"
#include "stages/retarget/foot_yaw_range.h"
#include "tests/support/demo_motion.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

// A revolute joint's <limit lower=... upper=...> from the URDF text (the first one not commented out).
std::pair<double, double> UrdfLimits(const std::string& urdf, const std::string& joint) {
  std::ifstream in(urdf);
  std::stringstream text;
  text << in.rdbuf();
  const std::string all = text.str();
  const size_t at = all.find("<joint name=\"" + joint + "\"");
  EXPECT_NE(at, std::string::npos) << joint;
  size_t limit = all.find("<limit", at);
  // Skip a commented-out limit (HRP-4C's URDF keeps its old ±1.5717 rad hip yaw in a comment).
  while (limit != std::string::npos && all.substr(all.rfind('\n', limit) + 1, limit - all.rfind('\n', limit)).find("<!--") != std::string::npos) {
    limit = all.find("<limit", limit + 1);
  }
  const auto attribute = [&](const std::string& name) {
    const size_t found = all.find(name + "=\"", limit);
    return std::stod(all.substr(found + name.size() + 2));
  };
  return {attribute("lower"), attribute("upper")};
}

Model LoadWithRanges(const std::string& urdf, const RobotMap& map) {
  ModelOptions options;
  options.floating_base = FloatingBaseFromName(map.floating_base);
  options.joint_ranges = map.joint_ranges;
  return Model::Load(urdf, options);
}

// G1's feet turn by the hip yaw alone (its ankle pitches and rolls), within the map's [joint_ranges].
TEST(FootYawRange, G1FeetTurnByTheHipYawWithinTheMapsRange) {
  const RobotMap map = LoadRobotMap(testing::SourcePath(testing::kG1Map));
  const Model model = LoadWithRanges(testing::SourcePath(testing::kG1Urdf), map);
  Workspace workspace(model);
  for (const std::string side : {"left", "right"}) {
    const YawRange range = FootYawRange(model, workspace, model.defaultQ(), model.findLinkIndex("pelvis"),
                                        model.findLinkIndex(side + "_ankle_roll_link"));
    const auto urdf = UrdfLimits(testing::SourcePath(testing::kG1Urdf), side + "_hip_yaw_joint");
    const auto& mapped = map.joint_ranges.at(side + "_hip_yaw_joint");
    EXPECT_NEAR(range.lower, std::max(urdf.first, mapped[0]), 1e-12) << side;
    EXPECT_NEAR(range.upper, std::min(urdf.second, mapped[1]), 1e-12) << side;
  }
}

// HRP-4C's by its hip yaw (j1/j7) and its ankle yaw (j_5.5/j_11.5), both about the vertical.
TEST(FootYawRange, Hrp4cFeetTurnByHipAndAnkleYaw) {
  SYN_REQUIRE_SHARED("robots/humanoid_synergies/HRP4c_optitrack_model.urdf");
  const std::string urdf = testing::SharedPath("robots/humanoid_synergies/HRP4c_optitrack_model.urdf");
  const RobotMap map = LoadRobotMap(testing::SourcePath("manifests/robots/hrp4c.toml"));
  const Model model = LoadWithRanges(urdf, map);
  Workspace workspace(model);
  for (const auto& [foot, hip, ankle] : {std::tuple<std::string, std::string, std::string>{"RL_foot", "j1", "j_5.5"},
                                         {"LL_foot", "j7", "j_11.5"}}) {
    const YawRange range = FootYawRange(model, workspace, model.defaultQ(), model.findLinkIndex("hip_base"), model.findLinkIndex(foot));
    const auto a = UrdfLimits(urdf, hip), b = UrdfLimits(urdf, ankle);
    EXPECT_NEAR(range.lower, a.first + b.first, 1e-12) << foot;
    EXPECT_NEAR(range.upper, a.second + b.second, 1e-12) << foot;
  }
}

// A foot turned 170° and tilted: held at the range's end about the pelvis's vertical, its tilt as it was
// (the angle between its sole normal and the pelvis's vertical), and nothing done within the range.
TEST(FootYawRange, HeldFeetKeepTheirTilt) {
  const YawRange range{-1.2, 0.8};
  const Eigen::Quaterniond pelvis(Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitY()));
  const Eigen::Quaterniond reference(Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitX()));
  const Eigen::Quaterniond tilt(Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitY()));
  for (const double turn : {170.0 * M_PI / 180.0, -2.0, 0.5}) {
    SCOPED_TRACE(turn);
    Eigen::Quaterniond foot = pelvis * Eigen::Quaterniond(Eigen::AngleAxisd(turn, Eigen::Vector3d::UnitZ())) * tilt * reference;
    const Eigen::Quaterniond asked = foot;
    const bool held = HoldFootYaw(pelvis, reference, range, foot);
    EXPECT_EQ(held, turn < range.lower || turn > range.upper);
    const double expected = std::clamp(turn, range.lower, range.upper);
    // The held deviation is the expected turn followed by the same tilt.
    const Eigen::Quaterniond deviation = pelvis.conjugate() * foot * reference.conjugate();
    const Eigen::Quaterniond wanted = Eigen::Quaterniond(Eigen::AngleAxisd(expected, Eigen::Vector3d::UnitZ())) * tilt;
    EXPECT_LT(deviation.angularDistance(wanted), 1e-9);
    if (!held) {
      EXPECT_LT(foot.angularDistance(asked), 1e-12);
    }
  }
}

}  // namespace
}  // namespace syn
