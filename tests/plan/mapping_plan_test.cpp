// The manifest's `mapping` chooses the route: "osc" puts syn-simulate between retarget and segment.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>

#include "tests/support/demo_motion.h"
#include "tests/support/run_command.h"
#include "tests/support/shared_data.h"

namespace syn::testing {
namespace {

namespace fs = std::filesystem;

class MappingPlan : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = (fs::temp_directory_path() / ("syn_mapping_" + std::to_string(::getpid()) + "_" +
                                         ::testing::UnitTest::GetInstance()->current_test_info()->name()))
               .string();
    fs::remove_all(dir_);
    fs::create_directories(dir_ + "/captures");
    fs::copy_file(SourcePath("datasets/demo/02_01.bvh"), dir_ + "/captures/02_01.bvh");
  }
  void TearDown() override { fs::remove_all(dir_); }

  CommandResult plan(const std::string& extra) {
    std::ofstream(dir_ + "/tiny.toml") << "name = \"tiny\"\nroot = \"captures\"\n"
                                       << "model = \"" << SourcePath(kG1Urdf) << "\"\n"
                                       << "robot_map = \"" << SourcePath(kG1Map) << "\"\n"
                                       << "markerset = \"" << SourcePath("manifests/markersets/cmu-bvh.toml") << "\"\n"
                                       << extra << "[[trial]]\nid = \"walk\"\nfile = \"02_01.bvh\"\n";
    return RunCommand("cd " + dir_ + " && " + BinPath("syn-plan") + " tiny.toml -o outputs/tiny/rules.mk");
  }
  std::string rules() {
    std::ifstream in(dir_ + "/outputs/tiny/rules.mk");
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
  }

  std::string dir_;
};

TEST_F(MappingPlan, KinematicByDefault) {
  ASSERT_EQ(plan("").exit_code, 0);
  const std::string text = rules();
  EXPECT_EQ(text.find("syn-simulate"), std::string::npos);
  EXPECT_NE(text.find("syn-retarget outputs/tiny/trials/walk/markers.h5 -o $@"), std::string::npos) << text;
  EXPECT_NE(text.find("outputs/tiny/trials/walk/motion.h5: outputs/tiny/trials/walk/markers.h5"), std::string::npos) << text;
}

TEST_F(MappingPlan, OscRunsSimulateBetweenRetargetAndSegment) {
  ASSERT_EQ(plan("[retarget]\nmapping = \"osc\"\n[simulate]\nkp = 300\n").exit_code, 0);
  const std::string text = rules();
  // retarget writes the kinematic motion, simulate reads it and writes the motion segment reads.
  EXPECT_NE(text.find("outputs/tiny/trials/walk/kinematic_motion.h5: outputs/tiny/trials/walk/markers.h5"), std::string::npos) << text;
  EXPECT_NE(text.find("outputs/tiny/trials/walk/motion.h5: outputs/tiny/trials/walk/kinematic_motion.h5"), std::string::npos) << text;
  EXPECT_NE(text.find("syn-simulate outputs/tiny/trials/walk/kinematic_motion.h5 -o $@"), std::string::npos) << text;
  EXPECT_NE(text.find("--kp 300"), std::string::npos) << text;
  EXPECT_NE(text.find("outputs/tiny/trials/walk/segments.h5: outputs/tiny/trials/walk/motion.h5"), std::string::npos) << text;
  // The simulation has its own parameter stamp; syn-retarget is never told about the mapping.
  EXPECT_TRUE(fs::exists(dir_ + "/outputs/tiny/params/walk.simulate.json"));
  EXPECT_EQ(text.find("--mapping"), std::string::npos) << text;
}

// The contact mode is a syn-simulate parameter like the gains: on its command line and in its stamp, so
// switching a manifest to the ground re-runs the simulations (and only them and what follows).
TEST_F(MappingPlan, GroundContactReachesTheSimulationAndItsStamp) {
  ASSERT_EQ(plan("[retarget]\nmapping = \"osc\"\n[simulate]\ncontact = \"ground\"\n").exit_code, 0);
  const std::string text = rules();
  EXPECT_NE(text.find("syn-simulate outputs/tiny/trials/walk/kinematic_motion.h5 -o $@"), std::string::npos) << text;
  EXPECT_NE(text.find("--contact ground"), std::string::npos) << text;
  std::ifstream stamp(dir_ + "/outputs/tiny/params/walk.simulate.json");
  std::ostringstream stamp_text;
  stamp_text << stamp.rdbuf();
  EXPECT_NE(stamp_text.str().find("\"contact\":\"ground\""), std::string::npos) << stamp_text.str();
  const std::string retarget_stamp = dir_ + "/outputs/tiny/params/walk.retarget.json";
  ASSERT_TRUE(fs::exists(retarget_stamp));
  const auto retarget_written = fs::last_write_time(retarget_stamp);
  ASSERT_EQ(plan("[retarget]\nmapping = \"osc\"\n").exit_code, 0);
  EXPECT_EQ(rules().find("--contact ground"), std::string::npos);
  EXPECT_EQ(fs::last_write_time(retarget_stamp), retarget_written) << "the retarget stamp did not change";
}

TEST_F(MappingPlan, UnknownMappingIsAnErrorAtItsLine) {
  const CommandResult result = plan("[retarget]\nmapping = \"dynamic\"\n");
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.output.find("tiny.toml:7"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("mapping must be \"kinematic\" or \"osc\""), std::string::npos) << result.output;
}

// A value the stage refuses fails the plan at the trial's line ([[trial]], line 10 here) with the stage's own message, before make
// runs anything, and leaves no rules behind; the same names with good values plan.
TEST_F(MappingPlan, ValuesTheStagesRefuseFailThePlan) {
  CommandResult result = plan("[retarget]\nmapping = \"osc\"\n[simulate]\ncontact = \"floor\"\n");
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.output.find("tiny.toml:10: trial walk: syn-simulate refuses its [simulate] parameters: --contact floor"),
            std::string::npos)
      << result.output;
  EXPECT_FALSE(fs::exists(dir_ + "/outputs/tiny/rules.mk"));
  result = plan("[retarget]\nfriction = -1\n");
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.output.find("syn-retarget refuses its [retarget] parameters: --friction -1: --friction must be > 0"),
            std::string::npos)
      << result.output;
  result = plan("[segment]\nmin_duration = -2\n");
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.output.find("syn-segment refuses"), std::string::npos) << result.output;
  result = plan("[retarget]\nfriction = 0.6\nmapping = \"osc\"\n[simulate]\ncontact = \"ground\"\n");
  EXPECT_EQ(result.exit_code, 0) << result.output;
}

}  // namespace
}  // namespace syn::testing
