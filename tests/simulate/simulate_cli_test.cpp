// syn-simulate's command line: bad usage exits 2, bad data exits 1 and leaves no output, and
// --print-parameters gives what syn-plan stamps.
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include <gtest/gtest.h>

#include "tests/support/demo_motion.h"
#include "tests/support/run_command.h"
#include "tests/support/shared_data.h"

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

TEST(SimulateCli, PrintParametersGivesEveryFlag) {
  const CommandResult result = RunCommandStdout(BinPath("syn-simulate") + " --print-parameters --kp 300 --no-effort-limits --balance-gain 2");
  ASSERT_EQ(result.exit_code, 0);
  EXPECT_EQ(result.output,
            "{\"balance_gain\":2.0,\"contact\":\"none\",\"damping\":0.001,\"floating_base\":\"auto\",\"independence_cutoff\":0.7,"
            "\"integrator\":\"euler\",\"kp\":300.0,\"kv\":25.0,\"limit_frequency\":100.0,\"no_balance\":false,\"no_effort_limits\":true,"
            "\"no_joint_limits\":false,\"rate\":1000.0,\"step_adjustment\":0.3,\"support_margin\":0.025,\"swing_lift\":0.04,\"targets\":\"kinematic\"}\n");
}

}  // namespace
}  // namespace syn::testing
