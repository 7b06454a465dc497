// Every syn-* tool follows the same command-line conventions (DESIGN.md):
// --help names the tool and exits 0, --version prints it, bad usage exits 2,
// bad data exits 1 with a located message.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include <nlohmann/json.hpp>

#include "tests/support/run_command.h"
#include "tests/support/scratch_file.h"
#include "tests/support/shared_data.h"

namespace syn::testing {
namespace {

std::vector<std::string> Tools() {
  std::vector<std::string> tools;
  for (const auto& entry : std::filesystem::directory_iterator(SYN_BIN_DIR)) {
    const std::string name = entry.path().filename().string();
    if (name.rfind("syn-", 0) == 0) tools.push_back(name);
  }
  std::sort(tools.begin(), tools.end());
  return tools;
}

std::string ScratchDir() { return ProcessScratchDir("syn_cli_").string(); }

TEST(Cli, ToolsAreBuilt) {
  const auto tools = Tools();
  EXPECT_NE(std::find(tools.begin(), tools.end(), "syn-ingest"), tools.end());
  EXPECT_NE(std::find(tools.begin(), tools.end(), "syn-inspect"), tools.end());
}

TEST(Cli, EveryToolHasHelpVersionAndUsageExitCode) {
  for (const std::string& tool : Tools()) {
    SCOPED_TRACE(tool);
    const CommandResult help = RunCommand(BinPath(tool) + " --help");
    EXPECT_EQ(help.exit_code, 0) << help.output;
    EXPECT_NE(help.output.find("Usage"), std::string::npos) << help.output;
    EXPECT_NE(help.output.find(tool), std::string::npos) << help.output;
    const CommandResult version = RunCommand(BinPath(tool) + " --version");
    EXPECT_EQ(version.exit_code, 0);
    EXPECT_NE(version.output.find(tool + " "), std::string::npos) << version.output;
    const CommandResult bad_flag = RunCommand(BinPath(tool) + " --no-such-flag");
    EXPECT_EQ(bad_flag.exit_code, 2) << bad_flag.output;
    const CommandResult no_arguments = RunCommand(BinPath(tool));
    EXPECT_EQ(no_arguments.exit_code, 2) << no_arguments.output;
  }
}

TEST(Cli, IngestRefusesBadValuesAsUsage) {
  const std::string out = ScratchDir() + "/x.markers.h5";
  const CommandResult result = RunCommand(BinPath("syn-ingest") + " /dev/null -o " + out + " --units furlongs");
  EXPECT_EQ(result.exit_code, 2) << result.output;
}

TEST(Cli, IngestOfUnknownContentExitsOneWithByteOffset) {
  const std::string dir = ScratchDir();
  std::ofstream(dir + "/garbage.dat") << "this is not a capture file\n";
  const CommandResult result = RunCommand(BinPath("syn-ingest") + " " + dir + "/garbage.dat -o " + dir + "/g.h5");
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_NE(result.output.find("garbage.dat: byte offset 0"), std::string::npos) << result.output;
  EXPECT_FALSE(std::filesystem::exists(dir + "/g.h5"));
}

TEST(Cli, IngestOfMissingFileExitsOne) {
  const std::string dir = ScratchDir();
  const CommandResult result = RunCommand(BinPath("syn-ingest") + " " + dir + "/nope.c3d -o " + dir + "/n.h5");
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_NE(result.output.find("nope.c3d"), std::string::npos) << result.output;
}

TEST(Cli, InspectOfNonHdf5ExitsOne) {
  const CommandResult result = RunCommand(BinPath("syn-inspect") + " " + SourcePath("README.md"));
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_NE(result.output.find("not an HDF5 file"), std::string::npos) << result.output;
}

// syn-plan learns stage parameters from --print-parameters: every flag must reach it, and with it the
// output's `parameters` attribute (the IK's tolerance did not, before it became an option).
TEST(Cli, PrintParametersCarriesEveryFlagWithoutInputs) {
  const CommandResult defaults = RunCommand(BinPath("syn-retarget") + " --print-parameters");
  ASSERT_EQ(defaults.exit_code, 0) << defaults.output;
  const nlohmann::json printed = nlohmann::json::parse(defaults.output);
  EXPECT_EQ(printed["ik_function_tolerance"], 1e-3);
  EXPECT_EQ(printed["scale"], "auto");
  EXPECT_EQ(printed["floating_base"], "map");
  const CommandResult changed = RunCommand(BinPath("syn-retarget") +
                                           " --print-parameters --ik-function-tolerance 1e-5 --scale 0.5 --floating-base free");
  ASSERT_EQ(changed.exit_code, 0) << changed.output;
  const nlohmann::json set = nlohmann::json::parse(changed.output);
  EXPECT_EQ(set["ik_function_tolerance"], 1e-5);
  EXPECT_EQ(set["scale"], 0.5);
  EXPECT_EQ(set["floating_base"], "free");
  const CommandResult bad = RunCommand(BinPath("syn-retarget") + " --print-parameters --scale tall");
  EXPECT_EQ(bad.exit_code, 2);
  EXPECT_NE(bad.output.find("--scale"), std::string::npos) << bad.output;
  for (const char* tool : {"syn-ingest", "syn-segment", "syn-synergies", "syn-evaluate", "syn-library"}) {
    const CommandResult result = RunCommand(BinPath(tool) + " --print-parameters");
    ASSERT_EQ(result.exit_code, 0) << tool << ": " << result.output;
    EXPECT_TRUE(nlohmann::json::parse(result.output).is_object()) << tool;
  }
}

}  // namespace
}  // namespace syn::testing
