// syn-plan's rules rebuild exactly what a change affects (issue: manifest-driven make).
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <vector>

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

// Runs `make all` in `dir` as the leader of a new process group, with the writer of every file ending in
// `pause_suffix` paused just before its rename (common/file_bytes.h, PauseBeforeRenameIfRequested). Started
// with fork/exec rather than `sh -c '... &'`: a non-interactive shell starts background jobs with SIGINT
// ignored, and then SIGINT would test nothing.
pid_t StartPausedMake(const std::string& dir, const std::string& pause_suffix) {
  const pid_t pid = ::fork();
  if (pid != 0) return pid;
  ::setsid();
  if (::chdir(dir.c_str()) != 0) ::_exit(127);
  ::setenv("SYN_TEST_PAUSE_BEFORE_RENAME", pause_suffix.c_str(), 1);
  if (std::freopen("run.log", "w", stdout) == nullptr) ::_exit(127);
  ::dup2(STDOUT_FILENO, STDERR_FILENO);
  const std::string bin = "SYN_BIN=" + std::string(SYN_BIN_DIR);
  ::execlp("make", "make", "-s", "-f", "outputs/tiny/rules.mk", bin.c_str(), "all", static_cast<char*>(nullptr));
  ::_exit(127);
}

std::string ReadWholeFile(const std::string& path) {
  std::ifstream in(path);
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// Temporaries (NAME.tmp-<pid>) beside `final_path`.
std::vector<std::string> TemporariesOf(const std::string& final_path) {
  std::vector<std::string> found;
  const fs::path target(final_path);
  for (const auto& entry : fs::directory_iterator(target.parent_path())) {
    const std::string name = entry.path().filename().string();
    if (name.rfind(target.filename().string() + ".tmp-", 0) == 0) found.push_back(entry.path().string());
  }
  return found;
}

TEST_F(IncrementalMake, KilledJobLeavesNoFileTakenAsDone) {
  // A manifest with a robot, so the trial runs ingest and then retarget (the shortest bundled capture).
  std::ofstream(dir_ + "/tiny.toml") << "name = \"tiny\"\nroot = \"captures\"\n"
                                     << "model = \"" << SourcePath("datasets/robots/unitree_g1/g1_29dof.urdf") << "\"\n"
                                     << "robot_map = \"" << SourcePath("manifests/robots/g1.toml") << "\"\n"
                                     << "markerset = \"" << SourcePath("manifests/markersets/cmu-bvh.toml") << "\"\n"
                                     << "[[trial]]\nid = \"jacks\"\nfile = \"14_14_excerpt.bvh\"\n";
  ASSERT_EQ(plan().exit_code, 0);
  const std::string motion = dir_ + "/outputs/tiny/trials/jacks/motion.h5";
  const std::string motion_target = "outputs/tiny/trials/jacks/motion.h5";

  for (const int signal : {SIGKILL, SIGTERM, SIGINT}) {
    SCOPED_TRACE(std::string("signal ") + strsignal(signal));
    fs::remove(motion);
    fs::remove(motion + ".log");
    // syn-retarget has written the whole of motion.h5.tmp-<pid> and is about to rename it: the worst moment.
    const pid_t make_pid = StartPausedMake(dir_, "motion.h5");
    ASSERT_GT(make_pid, 0);
    // The stage's stderr goes to motion.h5.log (syn-plan's rules), where the hook says it has paused.
    bool paused = false;
    for (int tick = 0; tick < 1200 && !paused; ++tick) {  // up to 120 s on a loaded machine
      paused = ReadWholeFile(motion + ".log").find("test hook: paused before renaming") != std::string::npos;
      if (!paused) ::usleep(100000);
    }
    const std::vector<std::string> temporaries = TemporariesOf(motion);
    ::kill(-make_pid, signal);  // the whole group: make, its shell and syn-retarget
    int status = 0;
    ::waitpid(make_pid, &status, 0);
    for (int tick = 0; tick < 100 && ::kill(-make_pid, 0) == 0; ++tick) ::usleep(100000);  // the group is gone
    ASSERT_TRUE(paused) << "syn-retarget never reached the rename: " << ReadWholeFile(dir_ + "/run.log")
                        << ReadWholeFile(motion + ".log");
    EXPECT_EQ(temporaries.size(), 1u) << "the complete temporary should exist when the signal lands";
    EXPECT_FALSE(WIFEXITED(status) && WEXITSTATUS(status) == 0) << "make finished although it was killed";

    // Nothing that looks finished: no motion.h5, and make still wants to build it (a leftover temporary, as
    // SIGKILL leaves, never counts as done).
    EXPECT_FALSE(fs::exists(motion)) << "a killed stage left " << motion << " behind";
    EXPECT_EQ(pendingOutputs().count(motion_target), 1u);

    // The rerun completes and writes a readable motion file.
    const CommandResult resumed = make("");
    ASSERT_EQ(resumed.exit_code, 0) << resumed.output;
    const CommandResult inspect = RunCommand(BinPath("syn-inspect") + " " + motion);
    EXPECT_EQ(inspect.exit_code, 0) << inspect.output;
    EXPECT_NE(inspect.output.find("synsculpt.motion"), std::string::npos);
    EXPECT_TRUE(pendingOutputs().empty());
    for (const std::string& leftover : TemporariesOf(motion)) fs::remove(leftover);
  }
}

// A launcher that reports success without running the job (srun can exit 0 for a step that never started)
// fails the rule: the job's output must exist and be newer than every prerequisite.
TEST_F(IncrementalMake, JobThatNeverRanFailsItsRule) {
  ASSERT_EQ(plan().exit_code, 0);
  const std::string walk_markers = "outputs/tiny/trials/walk/markers.h5";
  // `echo` stands in for such a launcher: it exits 0 and starts nothing.
  CommandResult never_ran = make("syn_launch=echo");
  EXPECT_NE(never_ran.exit_code, 0) << never_ran.output;
  EXPECT_NE(never_ran.output.find("markers.h5 was not written"), std::string::npos) << never_ran.output;
  EXPECT_FALSE(fs::exists(dir_ + "/" + walk_markers));

  // An output left by an earlier run does not count either once a prerequisite is newer.
  ASSERT_EQ(make("").exit_code, 0);
  // (Aged by moving the output's time back: a capture dated in the future would stay newer than any rerun.)
  fs::last_write_time(dir_ + "/" + walk_markers,
                      fs::last_write_time(dir_ + "/" + walk_markers) - std::chrono::seconds(2));
  never_ran = make("syn_launch=echo");
  EXPECT_NE(never_ran.exit_code, 0) << never_ran.output;
  EXPECT_NE(never_ran.output.find(walk_markers + " was not written (or is older than a prerequisite)"),
            std::string::npos)
      << never_ran.output;
  EXPECT_EQ(pendingOutputs(), (std::set<std::string>{walk_markers}));
  ASSERT_EQ(make("").exit_code, 0);
  EXPECT_TRUE(pendingOutputs().empty());
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

  // A name longer than the file system allows is a missing file too, not an escaped filesystem_error.
  const std::string too_long(5000, 'v');
  std::ofstream(dir_ + "/bad.toml") << "name = \"bad\"\nmodel = \"" << too_long << "\"\nroot = \"captures\"\n"
                                    << "[[trial]]\nid = \"a\"\nfile = \"" << too_long << "\"\n";
  result = RunCommand("cd " + dir_ + " && " + BinPath("syn-plan") + " bad.toml -o r.mk");
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.output.find("bad.toml:1: file not found: vvvv"), std::string::npos) << result.output.substr(0, 300);

  std::ofstream(dir_ + "/bad.toml") << "name = \"bad\"\nroot = \"captures\"\n[ingest]\nfill_gap = 3\n";
  result = RunCommand("cd " + dir_ + " && " + BinPath("syn-plan") + " bad.toml -o r.mk");
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.output.find("bad.toml:4: unknown ingest parameter 'fill_gap'"), std::string::npos) << result.output;
}

}  // namespace
}  // namespace syn::testing

namespace syn::testing {
namespace {

// Changing a segmentation parameter re-runs segment and what follows, for every trial, but not ingest or retarget.
TEST(IncrementalChain, SegmentThresholdReRunsSegmentOnward) {
  namespace fs = std::filesystem;
  const std::string dir = fs::temp_directory_path() / ("syn_chain_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir + "/captures");
  fs::copy_file(SourcePath("datasets/demo/14_14_excerpt.bvh"), dir + "/captures/a.bvh");
  fs::copy_file(SourcePath("datasets/demo/14_14_excerpt.bvh"), dir + "/captures/b.bvh");
  const auto write_manifest = [&](const std::string& threshold) {
    std::ofstream(dir + "/chain.toml") << "name = \"chain\"\nroot = \"captures\"\n"
                                       << "model = \"" << SourcePath("datasets/robots/unitree_g1/g1_29dof.urdf") << "\"\n"
                                       << "robot_map = \"" << SourcePath("manifests/robots/g1.toml") << "\"\n"
                                       << "markerset = \"" << SourcePath("manifests/markersets/cmu-bvh.toml") << "\"\n"
                                       << "[segment]\nthreshold = " << threshold << "\n"
                                       << "[evaluate]\nsamples = 5\n"
                                       << "[[trial]]\nid = \"a\"\nfile = \"a.bvh\"\nstyle = \"x\"\n"
                                       << "[[trial]]\nid = \"b\"\nfile = \"b.bvh\"\nstyle = \"y\"\n";
  };
  const std::string plan = "cd " + dir + " && " + BinPath("syn-plan") + " chain.toml -o outputs/chain/rules.mk";
  const std::string make = "cd " + dir + " && make -s -f outputs/chain/rules.mk SYN_BIN=" + std::string(SYN_BIN_DIR);
  write_manifest("0.75");
  ASSERT_EQ(RunCommand(plan).exit_code, 0);
  ASSERT_EQ(RunCommand(make + " all").exit_code, 0);
  write_manifest("2.5");
  ASSERT_EQ(RunCommand(plan).exit_code, 0);
  const CommandResult dry = RunCommand(make + " -n all");
  std::set<std::string> stages;
  std::istringstream lines(dry.output);
  for (std::string line; std::getline(lines, line);) {
    for (const char* stage : {"syn-ingest", "syn-retarget", "syn-segment", "syn-synergies", "syn-evaluate",
                              "syn-library", "syn-summary"}) {
      if (line.find(std::string("/") + stage + " ") != std::string::npos) stages.insert(stage);
    }
  }
  EXPECT_EQ(stages, (std::set<std::string>{"syn-segment", "syn-synergies", "syn-evaluate", "syn-library", "syn-summary"}))
      << dry.output;
  EXPECT_EQ(std::count(dry.output.begin(), dry.output.end(), '\n') > 0, true);
  EXPECT_NE(dry.output.find("trials/a/segments.h5"), std::string::npos);
  EXPECT_NE(dry.output.find("trials/b/segments.h5"), std::string::npos);
  fs::remove_all(dir);
}

// `make release` twice from clean outputs gives the same SHA-256: every stage's bytes are reproducible.
TEST(Release, TwoCleanBuildsGiveTheSameTar) {
  namespace fs = std::filesystem;
  const std::string dir = fs::temp_directory_path() / ("syn_release_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir + "/captures");
  fs::copy_file(SourcePath("datasets/demo/14_14_excerpt.bvh"), dir + "/captures/14_14_excerpt.bvh");
  fs::copy_file(SourcePath("datasets/demo/02_01.bvh"), dir + "/captures/02_01.bvh");
  std::ofstream(dir + "/tiny.toml") << "name = \"tiny\"\nversion = \"1.2.3\"\nroot = \"" << dir << "/captures\"\n"
                                    << "model = \"datasets/robots/unitree_g1/g1_29dof.urdf\"\n"
                                    << "robot_map = \"manifests/robots/g1.toml\"\n"
                                    << "markerset = \"manifests/markersets/cmu-bvh.toml\"\n"
                                    << "[evaluate]\nsamples = 5\n"
                                    << "[[trial]]\nid = \"jacks\"\nfile = \"14_14_excerpt.bvh\"\nmotion_class = \"jumping_jacks\"\n"
                                    << "[[trial]]\nid = \"walk\"\nfile = \"02_01.bvh\"\nmotion_class = \"walk\"\ndrop_first_frame = true\n";
  const std::string build_dir = fs::path(SYN_BIN_DIR).parent_path().string();
  std::vector<std::string> digests;
  // Same place, from scratch each time (the `inputs` attribute records paths as the rules give them).
  for (int run = 0; run < 2; ++run) {
    const std::string outputs = dir + "/outputs";
    fs::remove_all(outputs);
    const CommandResult result = RunCommand("make --no-print-directory -C " + std::string(SYN_SOURCE_DIR) +
                                            " release MANIFEST=" + dir + "/tiny.toml OUTPUTS=" + outputs +
                                            " BUILD_DIR=" + build_dir);
    ASSERT_EQ(result.exit_code, 0) << result.output;
    const std::string tar = outputs + "/tiny/release/tiny-1.2.3.tar";
    ASSERT_TRUE(fs::exists(tar)) << result.output;
    digests.push_back(RunCommand("sha256sum " + tar + " | cut -d' ' -f1").output);
    const CommandResult listing = RunCommand("tar tf " + tar);
    EXPECT_NE(listing.output.find("tiny-1.2.3/library/jumping_jacks.h5"), std::string::npos) << listing.output;
    EXPECT_NE(listing.output.find("tiny-1.2.3/trials/walk/synergies.h5"), std::string::npos);
    EXPECT_NE(listing.output.find("tiny-1.2.3/trials/walk/metrics.json"), std::string::npos);
    EXPECT_NE(listing.output.find("tiny-1.2.3/summary/segments.csv"), std::string::npos);
    EXPECT_NE(listing.output.find("tiny-1.2.3/SHA256SUMS"), std::string::npos);
    EXPECT_NE(listing.output.find("tiny-1.2.3/provenance.json"), std::string::npos);
    // SHA256SUMS lists every other file of the unpacked release, and each digest holds.
    const std::string unpacked = dir + "/unpacked";
    fs::remove_all(unpacked);
    fs::create_directories(unpacked);
    ASSERT_EQ(RunCommand("tar xf " + tar + " -C " + unpacked).exit_code, 0);
    const CommandResult check = RunCommand("cd " + unpacked + "/tiny-1.2.3 && sha256sum -c --strict SHA256SUMS");
    EXPECT_EQ(check.exit_code, 0) << check.output;
    const CommandResult files = RunCommand("cd " + unpacked + "/tiny-1.2.3 && find . -type f ! -name SHA256SUMS | wc -l");
    const CommandResult sums = RunCommand("wc -l < " + unpacked + "/tiny-1.2.3/SHA256SUMS");
    EXPECT_EQ(std::stoi(files.output), std::stoi(sums.output)) << "every file has its digest";
    EXPECT_EQ(static_cast<int>(std::count(check.output.begin(), check.output.end(), '\n')), std::stoi(sums.output))
        << check.output;
    EXPECT_EQ(check.output.find("FAILED"), std::string::npos) << check.output;
  }
  EXPECT_EQ(digests[0], digests[1]);
  EXPECT_EQ(digests[0].size(), 65u);  // 64 hex digits and a newline
  fs::remove_all(dir);
}

}  // namespace
}  // namespace syn::testing
