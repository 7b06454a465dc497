// syn-human's command line: exit codes, warnings, and both files written (or neither).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "common/file_bytes.h"
#include "tests/support/run_command.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

namespace fs = std::filesystem;

class HumanCli : public ::testing::Test {
 protected:
  void SetUp() override {
    directory_ = fs::temp_directory_path() / ("syn_human_cli_" + std::to_string(::getpid()));
    fs::create_directories(directory_);
  }
  void TearDown() override { fs::remove_all(directory_); }
  std::string path(const std::string& name) const { return (directory_ / name).string(); }
  fs::path directory_;
};

TEST_F(HumanCli, WritesTheModelAndItsRobotMap) {
  const auto result = testing::RunCommand(testing::BinPath("syn-human") + " --height 1.68 --mass 64.5 --sex f -o " +
                                          path("h.urdf") + " --robot-map-out " + path("h.toml"));
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_EQ(result.output.find("warning"), std::string::npos) << result.output;
  EXPECT_NE(ReadFileText(path("h.urdf")).find("<robot name=\"human_deleva\">"), std::string::npos);
  EXPECT_NE(ReadFileText(path("h.toml")).find("[feet.left]"), std::string::npos);
}

TEST_F(HumanCli, MissingMassWarnsAndUsesDeLevasReferenceSubject) {
  const auto result = testing::RunCommand(testing::BinPath("syn-human") + " --height 1.80 -o " + path("h.urdf"));
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("warning: no mass given: de Leva's reference male body mass 73 kg"), std::string::npos)
      << result.output;
}

TEST_F(HumanCli, BadValuesAreUsageErrorsAndWriteNothing) {
  for (const std::string flags : {"--sex x", "--height 175", "--mass 0"}) {
    SCOPED_TRACE(flags);
    const auto result = testing::RunCommand(testing::BinPath("syn-human") + " " + flags + " -o " + path("h.urdf"));
    EXPECT_EQ(result.exit_code, 2) << result.output;
    EXPECT_FALSE(fs::exists(path("h.urdf")));
  }
}

// Real data, end to end: the bundled CMU walk 02_01 on a human model at its capture's stature, retargeted and
// evaluated as make power-ratio does. Human joint power in walking is of the order of 1 W/kg (Farris & Sawicki
// 2012); the placeholder-inertia human URDF of the paper gave 72.6 W/kg here. Measured: 2.19 W/kg relative to
// the capture's T-pose calibration frame (3.18 relative to its first, mid-stride, frame).
TEST_F(HumanCli, BundledWalkCostsTheHumanModelAFewWattsPerKilogram) {
  const std::string bin = testing::BinPath(""), walk = testing::SourcePath("datasets/demo/02_01.bvh");
  const std::string markers = path("walk.markers.h5"), urdf = path("h.urdf"), map = path("h.toml");
  const std::string motion = path("walk.motion.h5"), metrics = path("walk.json");
  for (const std::string& command :
       {bin + "syn-ingest " + walk + " --drop-first-frame -o " + markers,
        bin + "syn-human --height-from-markers " + markers + " --mass 73 -o " + urdf + " --robot-map-out " + map,
        bin + "syn-retarget " + markers + " -o " + motion + " --model " + urdf + " --robot-map " + map +
            " --markerset " + testing::SourcePath("manifests/markersets/cmu-bvh.toml"),
        bin + "syn-evaluate " + motion + " --model " + urdf + " --robot-map " + map + " -o " + metrics}) {
    const auto result = testing::RunCommand(command);
    ASSERT_EQ(result.exit_code, 0) << command << "\n" << result.output;
    if (command.find("syn-human") != std::string::npos) {
      EXPECT_NE(result.output.find("calibration frame"), std::string::npos) << result.output;
    }
    if (command.find("syn-retarget") != std::string::npos) {
      EXPECT_NE(result.output.find("reference the calibration frame"), std::string::npos) << result.output;
    }
  }
  const nlohmann::json evaluated = nlohmann::json::parse(ReadFileText(metrics));
  const double power = evaluated.at("trial").at("mean_power_w_per_kg").get<double>();
  EXPECT_GT(power, 0.5);
  EXPECT_LT(power, 4.0);
}

}  // namespace
}  // namespace syn
