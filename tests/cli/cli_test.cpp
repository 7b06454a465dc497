// Every syn-* tool follows the same command-line conventions (DESIGN.md):
// --help names the tool and exits 0, --version prints it, bad usage exits 2,
// bad data exits 1 with a located message.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "tests/support/run_command.h"
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

std::string ScratchDir() {
  const auto dir = std::filesystem::temp_directory_path() / ("syn_cli_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir.string();
}

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

}  // namespace
}  // namespace syn::testing
