// syn-simulate's command line: bad usage exits 2, bad data exits 1 and leaves no output, and
// --print-parameters gives what syn-plan stamps.
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "common/intermediate_file.h"
#include "common/model.h"
#include "common/motion_file.h"
#include "common/robot_map.h"
#include "tests/support/demo_motion.h"
#include "tests/support/run_command.h"
#include "tests/support/shared_data.h"
#include "tests/support/synthetic_motions.h"

namespace syn::testing {
namespace {

std::string Tool() {
  return BinPath("syn-simulate") + " --model " + SourcePath(kG1Urdf) + " --robot-map " + SourcePath(kG1Map);
}

TEST(SimulateCli, BadRateIsAUsageError) {
  const CommandResult result = RunCommand(Tool() + " in.motion.h5 -o out.motion.h5 --rate 0");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("--rate must be in [10, 100000] Hz, got 0"), std::string::npos) << result.output;
}

TEST(SimulateCli, NonPositiveMomentWeightIsAUsageError) {
  const CommandResult result = RunCommand(Tool() + " in.motion.h5 -o out.motion.h5 --contact ground --moment-weight 0");
  EXPECT_EQ(result.exit_code, 2) << result.output;
  EXPECT_NE(result.output.find("--moment-weight must be in (0, 100], got 0"), std::string::npos) << result.output;
}

TEST(SimulateCli, UnknownContactModeIsAUsageError) {
  const CommandResult result = RunCommand(Tool() + " in.motion.h5 -o out.motion.h5 --contact moon");
  EXPECT_EQ(result.exit_code, 2) << result.output;
}

TEST(SimulateCli, NotAMotionFileFailsWithoutOutput) {
  const std::string dir = std::filesystem::temp_directory_path() / ("syn_simulate_cli_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  std::ofstream(dir + "/bad.motion.h5") << "not hdf5";
  const CommandResult result = RunCommand(Tool() + " " + dir + "/bad.motion.h5 -o " + dir + "/out.motion.h5");
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_NE(result.output.find("bad.motion.h5"), std::string::npos) << result.output;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    EXPECT_EQ(entry.path().filename().string().find("out.motion.h5"), std::string::npos) << entry.path();
  }
  std::filesystem::remove_all(dir);
}

TEST(SimulateCli, FallRecordNeedsTheGroundAndItsOwnFile) {
  const CommandResult no_ground = RunCommand(Tool() + " in.motion.h5 -o out.motion.h5 --fall-record fall.motion.h5");
  EXPECT_EQ(no_ground.exit_code, 2) << no_ground.output;
  EXPECT_NE(no_ground.output.find("--fall-record needs --contact ground"), std::string::npos) << no_ground.output;
  const CommandResult same = RunCommand(Tool() + " in.motion.h5 -o out.motion.h5 --contact ground --fall-record out.motion.h5");
  EXPECT_EQ(same.exit_code, 2) << same.output;
  EXPECT_NE(same.output.find("--fall-record must name another file than -o"), std::string::npos) << same.output;
}

TEST(SimulateCli, ControlTraceNeedsTheBalanceControllerAndItsOwnFile) {
  for (const char* flags : {"", "--contact ground --no-balance"}) {
    const CommandResult refused = RunCommand(Tool() + " in.motion.h5 -o out.motion.h5 --control-trace t.csv " + flags);
    EXPECT_EQ(refused.exit_code, 2) << refused.output;
    EXPECT_NE(refused.output.find("--control-trace needs --contact ground"), std::string::npos) << refused.output;
  }
  for (const char* clash : {"-o t.csv", "-o out.motion.h5 --fall-record t.csv"}) {
    const CommandResult same = RunCommand(Tool() + " in.motion.h5 --contact ground --control-trace t.csv " + clash);
    EXPECT_EQ(same.exit_code, 2) << same.output;
    EXPECT_NE(same.output.find("--control-trace must name another file"), std::string::npos) << same.output;
  }
}

// A robot shoved off its feet: exit 1 with the fall's time, no output, and with --fall-record the frames
// before the fall in a motion file the readers accept; with --control-trace the balance loop up to the fall.
TEST(SimulateCli, AFallLeavesNoOutputButItsRecord) {
  const Model model = Model::Load(SourcePath(kG1Urdf));
  const RobotMap map = LoadRobotMap(SourcePath(kG1Map));
  MotionData motion = StandingMotion(model, map, 2.0);
  motion.u[4] = 3.0;  // the base starts moving sideways at 3 m/s
  const std::string dir = std::filesystem::temp_directory_path() / ("syn_simulate_fall_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  {
    IntermediateWriter writer(dir + "/shoved.motion.h5", {kMotionSchema, kMotionSchemaVersion, "test", {}, nlohmann::json::array()});
    WriteMotionData(writer, motion);
    writer.commit();
  }
  const CommandResult result = RunCommand(Tool() + " " + dir + "/shoved.motion.h5 -o " + dir + "/out.motion.h5 --contact ground --fall-record " +
                                          dir + "/fall.motion.h5 --control-trace " + dir + "/fall.csv");
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_NE(result.output.find("fell at t = "), std::string::npos) << result.output;
  EXPECT_FALSE(std::filesystem::exists(dir + "/out.motion.h5"));
  const MotionData record = ReadMotionFile(dir + "/fall.motion.h5");
  EXPECT_GT(record.frames(), 1);
  EXPECT_LT(record.frames(), motion.frames());
  EXPECT_NE(result.output.find("the " + std::to_string(record.frames()) + " frames before the fall written to"), std::string::npos)
      << result.output;
  // The trace: a header and one line per control step up to the fall, which came after the record's last
  // frame (1 kHz, 1/120 s frames: 8-9 steps a frame).
  std::ifstream csv(dir + "/fall.csv");
  std::string line;
  ASSERT_TRUE(std::getline(csv, line));
  EXPECT_EQ(line.rfind("time,frame,balancing,", 0), 0u) << line;
  int64_t steps = 0;
  while (std::getline(csv, line)) ++steps;
  EXPECT_GE(steps, 8 * (record.frames() - 1)) << result.output;
  EXPECT_LE(steps, 9 * (record.frames() + 1)) << result.output;
  EXPECT_NE(result.output.find(std::to_string(steps) + " control steps written to"), std::string::npos) << result.output;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    const std::string name = entry.path().filename().string();
    EXPECT_TRUE(name == "shoved.motion.h5" || name == "fall.motion.h5" || name == "fall.csv") << "left behind: " << name;
  }
  std::filesystem::remove_all(dir);
}

TEST(SimulateCli, PrintParametersGivesEveryFlag) {
  const CommandResult result = RunCommandStdout(BinPath("syn-simulate") + " --print-parameters --kp 300 --no-effort-limits --balance-gain 2 --moment-weight 1.5 --no-swing-heading");
  ASSERT_EQ(result.exit_code, 0);
  EXPECT_EQ(result.output,
            "{\"balance_gain\":2.0,\"centre_line_turn\":30.0,\"contact\":\"none\",\"damping\":0.001,\"floating_base\":\"auto\",\"independence_cutoff\":0.7,"
            "\"integrator\":\"euler\",\"kp\":300.0,\"kv\":25.0,\"limit_frequency\":100.0,\"moment_weight\":1.5,\"no_balance\":false,\"no_effort_limits\":true,"
            "\"no_joint_limits\":false,\"no_swing_heading\":true,\"rate\":1000.0,\"step_adjustment\":0.3,\"support_margin\":0.025,\"swing_landing\":0.3,\"swing_lift\":0.04,\"targets\":\"kinematic\"}\n");
}

}  // namespace
}  // namespace syn::testing
