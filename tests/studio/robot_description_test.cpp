// The robot the studio gives player.js is the report's: PlayerRobotDescription (C++) against
// tools/report/urdf_fk.py's Robot.description() (numpy, written independently of the C++ URDF reader), for
// the bundled G1 and, when the shared datasets are present, H1 and HRP-4C (its virtual base chain).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "common/file_bytes.h"
#include "common/model.h"
#include "common/robot_map.h"
#include "tests/support/run_command.h"
#include "tests/support/shared_data.h"
#include "tools/studio/robot_description.h"

namespace syn {
namespace {

namespace fs = std::filesystem;

// Every number of `expected` within 1e-12 in `actual`, every other value equal, key by key.
void ExpectSame(const nlohmann::json& expected, const nlohmann::json& actual, const std::string& where) {
  if (expected.is_number()) {
    ASSERT_TRUE(actual.is_number()) << where;
    EXPECT_NEAR(expected.get<double>(), actual.get<double>(), 1e-12) << where;
  } else if (expected.is_array()) {
    ASSERT_TRUE(actual.is_array()) << where;
    ASSERT_EQ(expected.size(), actual.size()) << where;
    for (size_t i = 0; i < expected.size(); ++i) ExpectSame(expected[i], actual[i], where + "[" + std::to_string(i) + "]");
  } else if (expected.is_object()) {
    for (const auto& [key, value] : expected.items()) {
      ASSERT_TRUE(actual.contains(key)) << where << "." << key;
      ExpectSame(value, actual[key], where + "." + key);
    }
  } else {
    EXPECT_EQ(expected, actual) << where;
  }
}

void CompareWithNumpy(const std::string& urdf, const std::string& map_path) {
  const Model model = Model::Load(urdf);
  const nlohmann::json studio = PlayerRobotDescription(urdf, model, LoadRobotMap(map_path));
  const std::string dir = fs::temp_directory_path() / ("syn_robot_description_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  std::ofstream(dir + "/names.json") << nlohmann::json(model.coordinateNames()).dump();
  const std::string python = "import json, sys; sys.path.insert(0, sys.argv[1]); from urdf_fk import Robot; "
                             "print(json.dumps(Robot(sys.argv[2]).description(json.load(open(sys.argv[3])))))";
  const testing::CommandResult result = testing::RunCommandStdout(
      "/usr/bin/python3 -c '" + python + "' " + testing::SourcePath("tools/report") + " " + urdf + " " + dir + "/names.json");
  fs::remove_all(dir);
  ASSERT_EQ(result.exit_code, 0) << result.output;
  const nlohmann::json numpy = nlohmann::json::parse(result.output);
  ASSERT_EQ(studio["links"].size(), numpy["links"].size());
  ExpectSame(numpy, studio, "description");
  EXPECT_EQ(studio["feet"].size(), LoadRobotMap(map_path).feet.size());
}

TEST(RobotDescriptionTest, G1IsTheReportsDescription) {
  CompareWithNumpy(testing::SourcePath("datasets/robots/unitree_g1/g1_29dof.urdf"), testing::SourcePath("manifests/robots/g1.toml"));
}

TEST(RobotDescriptionTest, Hrp4cWithItsVirtualBaseIsTheReportsDescription) {
  SYN_REQUIRE_SHARED("robots/humanoid_synergies/HRP4c_optitrack_model.urdf");
  CompareWithNumpy(testing::SharedPath("robots/humanoid_synergies/HRP4c_optitrack_model.urdf"),
                   testing::SourcePath("manifests/robots/hrp4c.toml"));
}

TEST(RobotDescriptionTest, H1IsTheReportsDescription) {
  SYN_REQUIRE_SHARED("robots/unitree/h1.urdf");
  CompareWithNumpy(testing::SharedPath("robots/unitree/h1.urdf"), testing::SourcePath("manifests/robots/h1.toml"));
}

}  // namespace
}  // namespace syn
