#include "common/robot_map.h"

#include <gtest/gtest.h>
#include <tinyxml2.h>

#include <cmath>
#include <set>

#include "common/error.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

// The smallest map body a top-level key is tried with: one task.
const std::string kOneTask = "[[task]]\nlandmark = \"pelvis\"\nlink = \"p\"\n";

// The line a map text's first mistake is reported at (-1: none).
int64_t LineOfFirstError(const std::string& text) {
  try {
    (void)ParseRobotMap(text, "bad.toml");
  } catch (const DataError& error) {
    return error.where().line;
  }
  return -1;
}

TEST(RobotMap, G1FollowsTableOne) {
  const RobotMap map = LoadRobotMap(testing::SourcePath("manifests/robots/g1.toml"));
  ASSERT_EQ(map.tasks.size(), 9u);
  std::map<std::string, std::pair<TaskType, int>> expected = {
      {"pelvis", {TaskType::kPose, 1}},          {"left_foot", {TaskType::kPose, 1}},
      {"right_foot", {TaskType::kPose, 1}},      {"left_hand", {TaskType::kPose, 1}},
      {"right_hand", {TaskType::kPose, 1}},      {"head", {TaskType::kOrientation, 1}},
      {"upper_torso", {TaskType::kOrientation, 2}}, {"left_elbow", {TaskType::kOrientation, 2}},
      {"right_elbow", {TaskType::kOrientation, 2}}};
  for (const RobotTask& task : map.tasks) {
    ASSERT_TRUE(expected.count(task.landmark)) << task.landmark;
    EXPECT_EQ(task.type, expected[task.landmark].first) << task.landmark;
    EXPECT_EQ(task.priority, expected[task.landmark].second) << task.landmark;
  }
  EXPECT_EQ(map.posture_priority, 3);
  ASSERT_EQ(map.feet.size(), 2u);
  EXPECT_EQ(map.feet[0].sole_points.size(), 4u);
}

TEST(RobotMap, G1LinksExistInTheBundledUrdf) {
  const RobotMap map = LoadRobotMap(testing::SourcePath("manifests/robots/g1.toml"));
  // Link names read straight from the URDF, independently of our loader.
  tinyxml2::XMLDocument urdf;
  ASSERT_EQ(urdf.LoadFile(testing::SourcePath("datasets/robots/unitree_g1/g1_29dof.urdf").c_str()), tinyxml2::XML_SUCCESS);
  std::set<std::string> links, joints;
  for (auto* link = urdf.RootElement()->FirstChildElement("link"); link; link = link->NextSiblingElement("link")) {
    links.insert(link->Attribute("name"));
  }
  for (auto* joint = urdf.RootElement()->FirstChildElement("joint"); joint; joint = joint->NextSiblingElement("joint")) {
    joints.insert(joint->Attribute("name"));
  }
  EXPECT_NO_THROW(CheckRobotMapNames(
      map, [&](const std::string& name) { return links.count(name) > 0; },
      [&](const std::string& name) { return joints.count(name) > 0; }, "g1_29dof.urdf"));
  links.erase("torso_link");
  try {
    CheckRobotMapNames(
        map, [&](const std::string& name) { return links.count(name) > 0; },
        [&](const std::string& name) { return joints.count(name) > 0; }, "g1_29dof.urdf");
    FAIL() << "a missing link was accepted";
  } catch (const DataError& error) {
    EXPECT_NE(std::string(error.what()).find("g1.toml:"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("torso_link"), std::string::npos) << error.what();
  }
}

TEST(RobotMap, CalibrationStanceIsASecondStance) {
  const RobotMap plain = ParseRobotMap("[[task]]\nlandmark = \"pelvis\"\nlink = \"p\"\n", "plain.toml");
  EXPECT_FALSE(plain.calibration_stance.has_value());
  const RobotMap map = ParseRobotMap(
      "[[task]]\nlandmark = \"pelvis\"\nlink = \"p\"\n[reference_stance]\nknee = 0.1\n"
      "[calibration_stance]\nleft_shoulder = -1.5\n",
      "t.toml");
  ASSERT_TRUE(map.calibration_stance.has_value());
  EXPECT_DOUBLE_EQ(map.reference_stance.at("knee"), 0.1);
  EXPECT_DOUBLE_EQ(map.calibration_stance->at("left_shoulder"), -1.5);
  EXPECT_EQ(map.calibration_stance->count("knee"), 0u);
  try {
    CheckRobotMapNames(map, [](const std::string&) { return true; },
                       [](const std::string& joint) { return joint == "knee"; }, "robot");
    FAIL() << "expected an error";
  } catch (const DataError& error) {
    EXPECT_NE(std::string(error.what()).find("calibration_stance names joint 'left_shoulder'"), std::string::npos)
        << error.what();
  }
}

TEST(RobotMap, MistakesAreReportedAtTheirLine) {
  EXPECT_EQ(LineOfFirstError("[[task]]\nlandmark = \"pelvis\"\nlink = \"p\"\ntype = \"twist\"\n"), 4);
  EXPECT_EQ(LineOfFirstError("[[task]]\nlandmark = \"nose\"\nlink = \"p\"\n"), 2);
  EXPECT_EQ(LineOfFirstError("[[task]]\nlandmark = \"pelvis\"\nlink = \"p\"\npriority = 4\n"), 4);
  EXPECT_EQ(LineOfFirstError("[[task]]\nlandmark = \"pelvis\"\nlink = \"p\"\n[[task]]\nlandmark = \"pelvis\"\nlink = \"q\"\n"), 4);
  EXPECT_EQ(LineOfFirstError("robot = \"x\"\nspeed = 3\n"), 2);
  EXPECT_EQ(LineOfFirstError("robot = \"x\"\nproportions = \"arms\"\n"), 2);
  // The posture level indexes the three priority weights: out of range, fractional or huge is an error, not UB.
  EXPECT_EQ(LineOfFirstError("[posture]\npriority = 0\n"), 2);
  EXPECT_EQ(LineOfFirstError("[posture]\npriority = 55555755555555555\n"), 2);
  EXPECT_EQ(LineOfFirstError("[posture]\n\npriority = 2.5\n"), 3);
  EXPECT_EQ(LineOfFirstError("[[task]]\nlandmark = \"pelvis\"\nlink = \"p\"\npriority = 1e300\n"), 4);
}

// velocity_limit_scale: the multiple of the URDF velocity limits a frame's joint step is bounded by unless
// --velocity-limit-scale says (retarget.h), a number >= 0 (0: unbounded), 1 unless the map says.
TEST(RobotMap, VelocityLimitScaleIsANonNegativeMultipleOneUnlessTheMapSays) {
  EXPECT_EQ(LineOfFirstError("velocity_limit_scale = -1\n" + kOneTask), 1);
  EXPECT_EQ(LineOfFirstError("robot = \"x\"\nvelocity_limit_scale = \"fast\"\n" + kOneTask), 2);
  EXPECT_DOUBLE_EQ(ParseRobotMap(kOneTask, "t.toml").velocity_limit_scale, 1.0);
  EXPECT_DOUBLE_EQ(ParseRobotMap("velocity_limit_scale = 0\n" + kOneTask, "t.toml").velocity_limit_scale, 0.0);
  EXPECT_DOUBLE_EQ(LoadRobotMap(testing::SourcePath("manifests/robots/g1.toml")).velocity_limit_scale, 1.0);
  // HRP-4C's URDF speeds are under a person's pace: its map lets contacts rank above them (hrp4c.toml).
  EXPECT_GT(LoadRobotMap(testing::SourcePath("manifests/robots/hrp4c.toml")).velocity_limit_scale, 1.0);
}

// max_roll: how far planted feet may roll with the source (contact_enforcement.h), an angle in [0, π/2].
TEST(RobotMap, MaxRollIsAnAngleOnlyTheMapsThatWantItGive) {
  EXPECT_EQ(LineOfFirstError("max_roll = -0.1\n" + kOneTask), 1);
  EXPECT_EQ(LineOfFirstError("robot = \"x\"\nmax_roll = 2.0\n" + kOneTask), 2);
  EXPECT_EQ(LineOfFirstError("robot = \"x\"\nmax_roll = \"flat\"\n" + kOneTask), 2);
  EXPECT_DOUBLE_EQ(ParseRobotMap(kOneTask, "t.toml").max_roll, 0.0);  // flat unless the map says
  EXPECT_DOUBLE_EQ(ParseRobotMap("max_roll = 0.3\n" + kOneTask, "t.toml").max_roll, 0.3);
  EXPECT_GT(LoadRobotMap(testing::SourcePath("manifests/robots/g1.toml")).max_roll, 0.0);
  EXPECT_GT(LoadRobotMap(testing::SourcePath("manifests/robots/hrp4c.toml")).max_roll, 0.0);
}

// base_smoothing: the half-width (s) of contact enforcement's pelvis moves for plants, in [0, 1]; 0.1 unless
// the map says (HRP-4C's slow legs want them sharper).
TEST(RobotMap, BaseSmoothingIsATimeWithTheStagesDefault) {
  EXPECT_EQ(LineOfFirstError("base_smoothing = -0.01\n" + kOneTask), 1);
  EXPECT_EQ(LineOfFirstError("robot = \"x\"\nbase_smoothing = 2\n" + kOneTask), 2);
  EXPECT_EQ(LineOfFirstError("robot = \"x\"\nbase_smoothing = \"fast\"\n" + kOneTask), 2);
  EXPECT_DOUBLE_EQ(ParseRobotMap(kOneTask, "t.toml").base_smoothing, 0.1);
  EXPECT_DOUBLE_EQ(ParseRobotMap("base_smoothing = 0.05\n" + kOneTask, "t.toml").base_smoothing, 0.05);
  EXPECT_DOUBLE_EQ(LoadRobotMap(testing::SourcePath("manifests/robots/g1.toml")).base_smoothing, 0.1);
  EXPECT_LT(LoadRobotMap(testing::SourcePath("manifests/robots/hrp4c.toml")).base_smoothing, 0.1);
}

}  // namespace
}  // namespace syn

#include "common/model.h"

namespace syn {
namespace {

// [joint_ranges] narrows the URDF's limits for retargeting: read per joint, checked against the model's
// joints, and intersected with the URDF's by Model::Load (a range outside them is refused).
TEST(RobotMap, JointRangesNarrowTheUrdfLimits) {
  const RobotMap map = LoadRobotMap(testing::SourcePath("manifests/robots/g1.toml"));
  ASSERT_EQ(map.joint_ranges.count("left_hip_roll_joint"), 1u);
  const std::array<double, 2> roll = map.joint_ranges.at("left_hip_roll_joint");
  EXPECT_LT(roll[1], M_PI / 2);  // below the mirrored hip solution (pitch + π, π − roll, yaw + π)
  const std::string urdf = testing::SourcePath("datasets/robots/unitree_g1/g1_29dof.urdf");
  const Model plain = Model::Load(urdf);
  ModelOptions options;
  options.joint_ranges = map.joint_ranges;
  const Model narrowed = Model::Load(urdf, options);
  const auto& names = narrowed.coordinateNames();
  const auto index = [&](const std::string& joint) {
    return static_cast<Eigen::Index>(std::find(names.begin(), names.end(), joint) - names.begin());
  };
  const Eigen::Index left_roll = index("left_hip_roll_joint"), knee = index("left_knee_joint");
  EXPECT_DOUBLE_EQ(narrowed.qUpper()[left_roll], roll[1]);
  EXPECT_DOUBLE_EQ(narrowed.qLower()[left_roll], std::max(roll[0], plain.qLower()[left_roll]));
  EXPECT_GT(plain.qUpper()[left_roll], 2.9);  // the URDF's 170°
  EXPECT_DOUBLE_EQ(narrowed.qUpper()[knee], plain.qUpper()[knee]);  // joints not listed keep the URDF's
  options.joint_ranges = {{"left_knee_joint", {3.0, 4.0}}};          // G1's knee stops at 2.88 rad
  EXPECT_THROW((void)Model::Load(urdf, options), UsageError);

  EXPECT_EQ(LineOfFirstError(kOneTask + "[joint_ranges]\nhip = [0.5, 0.1]\n"), 5);
  EXPECT_EQ(LineOfFirstError(kOneTask + "[joint_ranges]\nhip = [0.5]\n"), 5);
  EXPECT_EQ(LineOfFirstError(kOneTask + "[joint_ranges]\nhip = 0.5\n"), 5);
  const RobotMap unknown = ParseRobotMap(kOneTask + "[joint_ranges]\nhip = [-0.5, 0.5]\n", "t.toml");
  try {
    CheckRobotMapNames(unknown, [](const std::string&) { return true; }, [](const std::string&) { return false; }, "robot");
    FAIL() << "a range for a joint the robot lacks was accepted";
  } catch (const DataError& error) {
    EXPECT_NE(std::string(error.what()).find("[joint_ranges] names joint 'hip'"), std::string::npos) << error.what();
  }
}

TEST(RobotMap, Hrp4cNamesExistInThePapersRobot) {
  SYN_REQUIRE_SHARED("robots/humanoid_synergies/HRP4c_optitrack_model.urdf");
  const Model model = Model::Load(testing::SharedPath("robots/humanoid_synergies/HRP4c_optitrack_model.urdf"));
  const RobotMap map = LoadRobotMap(testing::SourcePath("manifests/robots/hrp4c.toml"));
  EXPECT_EQ(map.tasks.size(), 9u);
  const auto& names = model.coordinateNames();
  EXPECT_NO_THROW(CheckRobotMapNames(
      map, [&](const std::string& link) { return model.findLinkIndex(link) >= 0; },
      [&](const std::string& joint) { return std::find(names.begin(), names.end(), joint) != names.end(); }, "HRP-4C"));
  EXPECT_FALSE(model.hasFreeBase());  // its own virtual base chain
  EXPECT_EQ(map.proportions, "chains");  // stance_alignment.h: its legs are shorter than its height says
}

TEST(RobotMap, H1MapNamesExistAndItsArmsAreFixed) {
  SYN_REQUIRE_SHARED("robots/unitree/h1.urdf");
  const std::string urdf = testing::SharedPath("robots/unitree/h1.urdf");
  const Model model = Model::Load(urdf);
  const RobotMap map = LoadRobotMap(testing::SourcePath("manifests/robots/h1.toml"));
  const auto& names = model.coordinateNames();
  EXPECT_NO_THROW(CheckRobotMapNames(
      map, [&](const std::string& link) { return model.findLinkIndex(link) >= 0; },
      [&](const std::string& joint) { return std::find(names.begin(), names.end(), joint) != names.end(); }, "H1"));
  EXPECT_TRUE(model.hasFreeBase());
  EXPECT_EQ(model.nu(), 16);  // 6 base + 10 leg joints: the arms are fixed in this URDF
}

}  // namespace
}  // namespace syn
