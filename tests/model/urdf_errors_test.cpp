// Malformed URDFs are refused with the file and line of the problem.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "common/error.h"
#include "common/urdf.h"
#include <nlohmann/json.hpp>
#include "tests/support/run_command.h"
#include "tests/support/scratch_file.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

int64_t ErrorLine(const std::string& xml, std::string* message = nullptr) {
  try {
    (void)ParseUrdf(xml, "robot.urdf");
  } catch (const DataError& error) {
    if (message) *message = error.what();
    return error.where().line;
  }
  return -1;
}

const char* kTwoLinks = R"(<robot name="r">
  <link name="a"/>
  <link name="b"/>
)";

TEST(UrdfErrors, EachMistakeIsLocated) {
  std::string message;
  // Missing parent link.
  EXPECT_EQ(ErrorLine(std::string(kTwoLinks) + R"(  <joint name="j" type="revolute">
    <parent link="nowhere"/><child link="b"/>
  </joint>
</robot>)", &message), 4);
  EXPECT_NE(message.find("parent link 'nowhere' does not exist"), std::string::npos) << message;
  // Unknown joint type.
  EXPECT_EQ(ErrorLine(std::string(kTwoLinks) + R"(  <joint name="j" type="ball"><parent link="a"/><child link="b"/></joint>
</robot>)", &message), 4);
  EXPECT_NE(message.find("unknown type 'ball'"), std::string::npos) << message;
  // Negative mass.
  EXPECT_EQ(ErrorLine(R"(<robot name="r">
  <link name="a">
    <inertial>
      <mass value="-2"/>
    </inertial>
  </link>
</robot>)", &message), 4);
  EXPECT_NE(message.find("negative mass"), std::string::npos) << message;
  // Non-numeric origin.
  EXPECT_EQ(ErrorLine(std::string(kTwoLinks) + R"(  <joint name="j" type="fixed">
    <parent link="a"/><child link="b"/>
    <origin xyz="0 zero 1"/>
  </joint>
</robot>)", &message), 6);
  EXPECT_NE(message.find("expected 3 numbers"), std::string::npos) << message;
  // Wrong count.
  EXPECT_EQ(ErrorLine(std::string(kTwoLinks) + R"(  <joint name="j" type="fixed"><parent link="a"/><child link="b"/>
    <origin rpy="0 1"/></joint>
</robot>)"), 5);
  // A cycle: a -> b -> a (and so no root).
  EXPECT_GT(ErrorLine(std::string(kTwoLinks) + R"(  <joint name="j1" type="fixed"><parent link="a"/><child link="b"/></joint>
  <joint name="j2" type="fixed"><parent link="b"/><child link="a"/></joint>
</robot>)", &message), 0);
  EXPECT_TRUE(message.find("cycle") != std::string::npos || message.find("root") != std::string::npos) << message;
  // A link with two parents.
  EXPECT_EQ(ErrorLine(R"(<robot name="r"><link name="a"/><link name="b"/><link name="c"/>
  <joint name="j1" type="fixed"><parent link="a"/><child link="c"/></joint>
  <joint name="j2" type="fixed"><parent link="b"/><child link="c"/></joint>
</robot>)"), 3);
  // XML syntax.
  // (tinyxml2 names the line of the unclosed element or of the mismatched close tag.)
  const int64_t syntax_line = ErrorLine("<robot name=\"r\">\n<link name=\"a\">\n</robot>\n");
  EXPECT_TRUE(syntax_line == 2 || syntax_line == 3) << syntax_line;
  // A zero axis on a moving joint.
  EXPECT_EQ(ErrorLine(std::string(kTwoLinks) + R"(  <joint name="j" type="revolute"><parent link="a"/><child link="b"/>
    <axis xyz="0 0 0"/></joint>
</robot>)"), 5);
}

TEST(UrdfErrors, CommentedJointsAreIgnored) {
  const RobotDescription robot = ParseUrdf(std::string(kTwoLinks) + R"(  <!-- <joint name="floating" type="floating"><parent link="a"/><child link="b"/></joint> -->
  <joint name="j" type="continuous"><parent link="a"/><child link="b"/><axis xyz="0 0 2"/></joint>
</robot>)", "robot.urdf");
  ASSERT_EQ(robot.joints.size(), 1u);
  EXPECT_EQ(robot.joints[0].name, "j");
  EXPECT_DOUBLE_EQ(robot.joints[0].axis.z(), 1.0);  // normalised
}

TEST(UrdfErrors, InspectExitsOneWithFileAndLine) {
  const testing::ScratchFile urdf("bad", ".urdf", std::string(kTwoLinks) + "  <joint name=\"j\" type=\"hinge\"><parent link=\"a\"/><child link=\"b\"/></joint>\n</robot>\n");
  const std::string& path = urdf.path();
  const testing::CommandResult result = testing::RunCommand(testing::BinPath("syn-inspect") + " " + path);
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_NE(result.output.find(path + ":4: joint 'j': unknown type 'hinge'"), std::string::npos) << result.output;
  const testing::CommandResult usage = testing::RunCommand(testing::BinPath("syn-inspect") + " " + path + " --floating-base sideways");
  EXPECT_EQ(usage.exit_code, 2) << usage.output;
}

TEST(UrdfErrors, InspectDescribesTheDefaultRobot) {
  const testing::CommandResult result =
      testing::RunCommandStdout(testing::BinPath("syn-inspect") + " " + testing::SourcePath("datasets/robots/unitree_g1/g1_29dof.urdf"));
  ASSERT_EQ(result.exit_code, 0);
  const nlohmann::json description = nlohmann::json::parse(result.output);
  EXPECT_EQ(description["nq"], 36);
  EXPECT_EQ(description["nu"], 35);
  EXPECT_EQ(description["floating_base"], "free");
  EXPECT_EQ(description["links"].size(), 40u);
}

// Unit inertias pasted on every link (the paper's HRP-4C and human models ship like that) are not an error,
// but would silently scale every torque: warned once, at the worst link's line.
TEST(UrdfWarnings, PlaceholderInertiasAreNamedOnce) {
  const std::string placeholder = R"(<robot name="r">
  <link name="torso">
    <inertial><mass value="10"/><inertia ixx="0.3" iyy="0.3" izz="0.1" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <link name="forearm">
    <inertial><mass value="0.5"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <link name="tool_frame">
    <inertial><mass value="1e-6"/><inertia ixx="1e-6" iyy="1e-6" izz="1e-6" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <joint name="elbow" type="revolute"><parent link="torso"/><child link="forearm"/>
    <axis xyz="0 1 0"/><limit lower="-1" upper="1" effort="1" velocity="1"/></joint>
  <joint name="tool" type="fixed"><parent link="forearm"/><child link="tool_frame"/></joint>
</robot>)";
  const RobotDescription description = ParseUrdf(placeholder, "robot.urdf");
  ASSERT_EQ(description.warnings.size(), 1u);
  EXPECT_EQ(description.warnings[0].rfind("robot.urdf:5: 1 link(s)", 0), 0u) << description.warnings[0];
  EXPECT_NE(description.warnings[0].find("'forearm'"), std::string::npos) << description.warnings[0];

  // The same robot with a forearm's real inertia (radius of gyration 0.1 m) is silent.
  std::string real = placeholder;
  real.replace(real.find(R"(ixx="1" iyy="1" izz="1")"), 23, R"(ixx="0.005" iyy="0.005" izz="0.001")");
  EXPECT_TRUE(ParseUrdf(real, "robot.urdf").warnings.empty());
}

}  // namespace
}  // namespace syn
