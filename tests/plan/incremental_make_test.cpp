// syn-plan's rules rebuild exactly what a change affects (issue: manifest-driven make).
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>

#include "tests/support/run_command.h"
#include "tests/support/shared_data.h"

namespace syn::testing {
namespace {

namespace fs = std::filesystem;

class IncrementalMake : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = (fs::temp_directory_path() / ("syn_plan_" + std::to_string(::getpid()) + "_" +
                                         ::testing::UnitTest::GetInstance()->current_test_info()->name()))
               .string();
    fs::remove_all(dir_);
    fs::create_directories(dir_ + "/captures");
    for (const char* trial : {"02_01", "14_14_excerpt"}) {
      fs::copy_file(SourcePath(std::string("datasets/demo/") + trial + ".bvh"), dir_ + "/captures/" + trial + ".bvh");
    }
    writeManifest("true");
  }
  void TearDown() override { fs::remove_all(dir_); }

  void writeManifest(const std::string& drop_first_frame_of_walk) {
    std::ofstream(dir_ + "/tiny.toml") << "name = \"tiny\"\nroot = \"captures\"\n"
                                       << "[[trial]]\nid = \"walk\"\nfile = \"02_01.bvh\"\nmotion_class = \"walk\"\n"
                                       << "drop_first_frame = " << drop_first_frame_of_walk << "\n"
                                       << "[[trial]]\nid = \"jacks\"\nfile = \"14_14_excerpt.bvh\"\n";
  }

  CommandResult plan() {
    return RunCommand("cd " + dir_ + " && " + BinPath("syn-plan") + " tiny.toml -o outputs/tiny/rules.mk");
  }
  CommandResult make(const std::string& flags) {
    return RunCommand("cd " + dir_ + " && make -s -f outputs/tiny/rules.mk SYN_BIN=" + std::string(SYN_BIN_DIR) + " " +
                      flags + " all");
  }
  // The targets `make -n` would rebuild, from its echoed syn-* commands.
  std::set<std::string> pendingOutputs() {
    const CommandResult dry = make("-n");
    std::set<std::string> outputs;
    std::istringstream lines(dry.output);
    for (std::string line; std::getline(lines, line);) {
      const size_t flag = line.find(" -o ");
      if (flag == std::string::npos || line.find("syn-") == std::string::npos) continue;
      const size_t end = line.find(' ', flag + 4);
      outputs.insert(line.substr(flag + 4, end - flag - 4));
    }
    return outputs;
  }

  std::string dir_;
};

TEST_F(IncrementalMake, RebuildsOnlyWhatAChangeAffects) {
  ASSERT_EQ(plan().exit_code, 0);
  const CommandResult first = make("");
  ASSERT_EQ(first.exit_code, 0) << first.output;
  EXPECT_NE(first.output.find("ingest"), std::string::npos) << "one progress line per job expected: " << first.output;
  EXPECT_TRUE(pendingOutputs().empty());
  EXPECT_EQ(make("--question").exit_code, 0) << "everything should be up to date";

  // Touching one capture re-runs that trial only.
  sleep(1);
  fs::last_write_time(dir_ + "/captures/02_01.bvh", fs::file_time_type::clock::now());
  EXPECT_EQ(pendingOutputs(), (std::set<std::string>{"outputs/tiny/trials/walk/markers.h5"}));
  ASSERT_EQ(make("").exit_code, 0);

  // Re-planning with the same manifest changes nothing.
  ASSERT_EQ(plan().exit_code, 0);
  EXPECT_TRUE(pendingOutputs().empty());

  // Changing one trial's parameter re-runs that trial's chain only.
  writeManifest("false");
  ASSERT_EQ(plan().exit_code, 0);
  EXPECT_EQ(pendingOutputs(), (std::set<std::string>{"outputs/tiny/trials/walk/markers.h5"}));
}

TEST_F(IncrementalMake, KilledJobLeavesNoFileTakenAsDone) {
  ASSERT_EQ(plan().exit_code, 0);
  // A stage killed mid-write leaves only NAME.tmp-<pid>, never NAME: simulate the leftover.
  fs::create_directories(dir_ + "/outputs/tiny/trials/walk");
  std::ofstream(dir_ + "/outputs/tiny/trials/walk/markers.h5.tmp-12345") << "partial";
  EXPECT_TRUE(pendingOutputs().count("outputs/tiny/trials/walk/markers.h5"));
  ASSERT_EQ(make("").exit_code, 0);
  EXPECT_TRUE(fs::exists(dir_ + "/outputs/tiny/trials/walk/markers.h5"));
}

TEST_F(IncrementalMake, ManifestMistakesAreLocated) {
  std::ofstream(dir_ + "/bad.toml") << "name = \"bad\"\nroot = \"captures\"\n[[trial]]\nid = \"a\"\nfile = \"02_01.bvh\"\n"
                                    << "[[trial]]\nid = \"a\"\nfile = \"02_01.bvh\"\n";
  CommandResult result = RunCommand("cd " + dir_ + " && " + BinPath("syn-plan") + " bad.toml -o r.mk");
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.output.find("bad.toml:6: duplicate trial id 'a'"), std::string::npos) << result.output;

  std::ofstream(dir_ + "/bad.toml") << "name = \"bad\"\nroot = \"captures\"\n[[trial]]\nid = \"a\"\nfile = \"nope.bvh\"\n";
  result = RunCommand("cd " + dir_ + " && " + BinPath("syn-plan") + " bad.toml -o r.mk");
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.output.find("bad.toml:3: trial 'a': capture file not found"), std::string::npos) << result.output;

  std::ofstream(dir_ + "/bad.toml") << "name = \"bad\"\nroot = \"captures\"\n[ingest]\nfill_gap = 3\n";
  result = RunCommand("cd " + dir_ + " && " + BinPath("syn-plan") + " bad.toml -o r.mk");
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.output.find("bad.toml:4: unknown ingest parameter 'fill_gap'"), std::string::npos) << result.output;
}

}  // namespace
}  // namespace syn::testing
