// The Makefile's test, configure and fuzz-smoke targets fail when they should. cmake and the fuzzers are
// replaced by small scripts on PATH (the real ones take minutes); make, ctest and the recipes are real.
#include <gtest/gtest.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "tests/support/run_command.h"
#include "tests/support/shared_data.h"

namespace syn::testing {
namespace {

namespace fs = std::filesystem;

class MakefileTargets : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = (fs::temp_directory_path() / ("syn_makefile_" + std::to_string(::getpid()) + "_" +
                                         ::testing::UnitTest::GetInstance()->current_test_info()->name()))
               .string();
    fs::remove_all(dir_);
    fs::create_directories(dir_ + "/fakebin");
    fs::create_directories(dir_ + "/build");
    // A cmake that records its arguments and does nothing else.
    writeScript(dir_ + "/fakebin/cmake", "#!/bin/sh\necho \"$*\" >> " + dir_ + "/cmake.log\n");
  }
  void TearDown() override { fs::remove_all(dir_); }

  static void writeScript(const std::string& path, const std::string& text) {
    std::ofstream(path) << text;
    fs::permissions(path, fs::perms::owner_all | fs::perms::group_read | fs::perms::others_read);
  }
  CommandResult make(const std::string& arguments) {
    // Without what the calling make passes down: run under `make sanitize-test`, its MAKEFLAGS carry
    // CMAKE_FLAGS=... as a command-line override, and make also exports its command-line variables
    // (CMAKE_FLAGS, BUILD_TYPE, BUILD_DIR) into the environment of every recipe, this test included.
    return RunCommand("env -u MAKEFLAGS -u MFLAGS -u MAKELEVEL -u CMAKE_FLAGS -u BUILD_TYPE -u BUILD_DIR -u JOBS PATH=" + dir_ + "/fakebin:$PATH make --no-print-directory -C " +
                      std::string(SYN_SOURCE_DIR) + " " + arguments);
  }
  std::string cmakeLog() {
    std::ifstream in(dir_ + "/cmake.log");
    std::ostringstream text;
    text << in.rdbuf();
    return text.str();
  }

  std::string dir_;
};

// An existing build directory is configured again when CMAKE_FLAGS change (CI's -DSYN_WERROR=ON used to be
// ignored when build/ existed), and not when they are the same or empty.
TEST_F(MakefileTargets, ConfigureHonoursNewFlagsOnAnExistingBuildDirectory) {
  std::ofstream(dir_ + "/build/CMakeCache.txt") << "# an existing build directory\n";
  const std::string build = " BUILD_DIR=" + dir_ + "/build";
  CommandResult result = make("configure" + build + " CMAKE_FLAGS=-DSYN_WERROR=ON");
  ASSERT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(cmakeLog().find("-DSYN_WERROR=ON"), std::string::npos) << "cmake was not run: " << cmakeLog();

  const std::string after_first = cmakeLog();
  ASSERT_EQ(make("configure" + build + " CMAKE_FLAGS=-DSYN_WERROR=ON").exit_code, 0);
  ASSERT_EQ(make("configure" + build).exit_code, 0);
  EXPECT_EQ(cmakeLog(), after_first) << "same or no flags: no need to configure again";

  ASSERT_EQ(make("configure" + build + " CMAKE_FLAGS=-DSYN_WERROR=OFF").exit_code, 0);
  EXPECT_NE(cmakeLog().find("-DSYN_WERROR=OFF"), std::string::npos) << cmakeLog();
}

// `make test` on a build directory without tests fails (ctest alone says "No tests were found" and exits 0).
TEST_F(MakefileTargets, TestFailsWhenThereAreNoTests) {
  std::ofstream(dir_ + "/build/CMakeCache.txt") << "# an existing build directory\n";
  std::ofstream(dir_ + "/build/CTestTestfile.cmake") << "# no tests\n";
  const CommandResult result = make("test BUILD_DIR=" + dir_ + "/build JOBS=1");
  EXPECT_NE(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("No tests were found"), std::string::npos) << result.output;
}

TEST_F(MakefileTargets, FuzzSmokeFailsWithoutFuzzers) {
  const CommandResult result = make("fuzz-smoke FUZZ_BUILD_DIR=" + dir_ + "/fuzz FUZZ_SECONDS=1");
  EXPECT_NE(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("no fuzzer"), std::string::npos) << result.output;
}

// Fake fuzzers: one that finds nothing (and insists on a per-input -timeout), one with a finding reported
// after many lines of output. The run fails, names the fuzzer, prints the finding and keeps the whole log.
TEST_F(MakefileTargets, FuzzSmokeFailsOnAFindingAndKeepsTheLog) {
  fs::create_directories(dir_ + "/fuzz/bin");
  writeScript(dir_ + "/fuzz/bin/quiet_fuzzer",
              "#!/bin/sh\ncase \"$*\" in *-timeout=*) ;; *) echo 'no -timeout given'; exit 3;; esac\n"
              "echo 'stat::number_of_executed_units: 1234'\nexit 0\n");
  const std::string fuzz = " FUZZ_BUILD_DIR=" + dir_ + "/fuzz FUZZ_SECONDS=1";
  CommandResult result = make("fuzz-smoke" + fuzz);
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("quiet_fuzzer: 1 s, 1234 inputs, no finding"), std::string::npos) << result.output;

  writeScript(dir_ + "/fuzz/bin/finding_fuzzer",
              "#!/bin/sh\necho 'FIRST LINE OF THE LOG'\nfor i in $(seq 1 100); do echo \"#$i NEW cov: 1\"; done\n"
              "echo '==1==ERROR: UndefinedBehaviorSanitizer: a finding'\nexit 1\n");
  result = make("fuzz-smoke" + fuzz);
  EXPECT_NE(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("finding_fuzzer: FAILED"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("UndefinedBehaviorSanitizer: a finding"), std::string::npos) << result.output;
  std::ifstream log(dir_ + "/fuzz/logs/finding_fuzzer.log");
  std::string first_line;
  std::getline(log, first_line);
  EXPECT_EQ(first_line, "FIRST LINE OF THE LOG") << "the whole log is kept";
}

// JOBS fuzzers run at once (CI's two cores each fuzz one): two fake fuzzers that each wait, up to 5 s, for
// the other to have started pass only when run together, and a run one at a time fails on them.
TEST_F(MakefileTargets, FuzzSmokeRunsJobsFuzzersAtOnce) {
  fs::create_directories(dir_ + "/fuzz/bin");
  for (const std::string name : {"left", "right"}) {
    const std::string other = name == "left" ? "right" : "left";
    writeScript(dir_ + "/fuzz/bin/" + name + "_fuzzer",
                "#!/bin/sh\ntouch " + dir_ + "/" + name + ".started\n"
                "for i in $(seq 1 50); do [ -f " + dir_ + "/" + other + ".started ] && exit 0; sleep 0.1; done\n"
                "echo 'the other fuzzer never started'; exit 1\n");
  }
  const std::string fuzz = " FUZZ_BUILD_DIR=" + dir_ + "/fuzz FUZZ_SECONDS=1";
  CommandResult result = make("fuzz-smoke JOBS=2" + fuzz);
  EXPECT_EQ(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("left_fuzzer: 1 s"), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("right_fuzzer: 1 s"), std::string::npos) << result.output;
  fs::remove(dir_ + "/left.started");
  fs::remove(dir_ + "/right.started");
  result = make("fuzz-smoke JOBS=1" + fuzz);
  EXPECT_NE(result.exit_code, 0) << result.output;
  EXPECT_NE(result.output.find("left_fuzzer: FAILED"), std::string::npos) << result.output;
}

}  // namespace
}  // namespace syn::testing
