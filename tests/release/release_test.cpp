// Dataset releases (issue 25): the demo release holds every trial's motion and the manifest's exports, its
// datasheet's totals equal the files', verify passes on a fresh release and names the file after a changed
// byte or a removed member, two clean builds give the same tar, and --rebuild finds a forged member.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <regex>
#include <set>
#include <sstream>

#include "common/error.h"
#include "common/file_bytes.h"
#include "common/motion_file.h"
#include "common/release_manifest.h"
#include "common/sha256.h"
#include "tests/support/run_command.h"
#include "tests/support/shared_data.h"
#include "tools/release/datasheet.h"
#include "tools/release/tar_archive.h"
#include "tools/release/trial_quality.h"

namespace syn::testing {
namespace {

namespace fs = std::filesystem;

// A tree whose manifests/ and datasets/ are symlinks into the source tree, with its own outputs/: the
// demo pipeline and release run there record the same relative paths as in the source tree.
std::string DemoTree(const fs::path& dir) {
  fs::create_directories(dir);
  for (const char* entry : {"manifests", "datasets"}) fs::create_directory_symlink(SourcePath(entry), dir / entry);
  const std::string in = "cd " + dir.string() + " && ";
  const CommandResult plan = RunCommand(in + BinPath("syn-plan") + " manifests/demo.toml -o outputs/demo/rules.mk");
  if (plan.exit_code != 0) return "syn-plan failed: " + plan.output;
  const CommandResult make = RunCommand(in + "make -s -j2 -f outputs/demo/rules.mk SYN_BIN=" + std::string(SYN_BIN_DIR) + " all");
  if (make.exit_code != 0) return "make failed: " + make.output;
  const CommandResult release = RunCommand(in + BinPath("syn-release") + " build manifests/demo.toml");
  if (release.exit_code != 0) return "syn-release build failed: " + release.output;
  return "";
}

class DemoRelease : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
#ifdef SYN_SANITIZED_BUILD
    return;  // the demo pipeline under ASan takes ~9 min per test; the release tests run in the Release build
#endif
    root_ = fs::temp_directory_path() / ("syn_release_" + std::to_string(::getpid()));
    fs::remove_all(root_);
    failure_ = DemoTree(root_ / "first");
    if (!failure_.empty()) return;
    fs::create_directories(root_ / "extracted");
    ExtractTar(tar(), (root_ / "extracted").string());
  }
  static void TearDownTestSuite() { fs::remove_all(root_); }
  void SetUp() override {
#ifdef SYN_SANITIZED_BUILD
    GTEST_SKIP() << "the demo release tests run in the Release test run, not under the sanitizers";
#endif
    ASSERT_TRUE(failure_.empty()) << failure_;
  }

  static std::string tar(const std::string& tree = "first") {
    return (root_ / tree / "outputs/demo/release/demo-0.1.0.tar").string();
  }
  static fs::path release() { return root_ / "extracted/demo-0.1.0"; }
  // A fresh copy of the extracted release to damage.
  static fs::path copy(const std::string& name) {
    const fs::path to = root_ / name / "demo-0.1.0";
    fs::remove_all(root_ / name);
    fs::create_directories(to.parent_path());
    fs::copy(release(), to, fs::copy_options::recursive);
    return to;
  }
  static CommandResult verify(const std::string& what, const std::string& flags = "") {
    return RunCommand(BinPath("syn-release") + " verify " + what + " " + flags);
  }
  static size_t Lines(const fs::path& file) {
    std::istringstream text(ReadFileText(file.string()));
    size_t lines = 0;
    for (std::string line; std::getline(text, line);) lines += !line.empty();
    return lines;
  }

  static fs::path root_;
  static std::string failure_;
};
fs::path DemoRelease::root_;
std::string DemoRelease::failure_;

TEST_F(DemoRelease, HoldsEveryTrialsMotionAndTheRequestedExports) {
  const ReleaseManifest manifest = ReadReleaseManifest(SourcePath("manifests/demo.toml"));
  ASSERT_EQ(manifest.trials.size(), 5u);
  // The manifest asks with the issue's names; they map to syn-export's formats.
  EXPECT_EQ(manifest.exports, (std::vector<std::string>{"robot-csv", "unitree-csv", "mjlab-npz", "mot"}));
  for (const ReleaseTrial& trial : manifest.trials) {
    const fs::path dir = release() / "trials" / trial.id;
    ASSERT_TRUE(fs::is_regular_file(dir / "motion.h5")) << trial.id;
    const MotionData motion = ReadMotionFile((dir / "motion.h5").string());
    // One row per frame in both CSV layouts, and the mot's nRows, as the motion has frames.
    EXPECT_EQ(Lines(dir / "motion.robot.csv"), static_cast<size_t>(motion.frames())) << trial.id;
    EXPECT_EQ(Lines(dir / "motion.unitree.csv"), static_cast<size_t>(motion.frames())) << trial.id;
    EXPECT_NE(ReadFileText((dir / "motion.mot").string()).find("nRows=" + std::to_string(motion.frames()) + "\n"),
              std::string::npos) << trial.id;
    const std::string npz = ReadFileText((dir / "motion.mjlab.npz").string());
    EXPECT_EQ(npz.substr(0, 2), "PK") << trial.id;
    EXPECT_NE(npz.find("body_pos_w.npy"), std::string::npos) << trial.id;
  }
}

TEST_F(DemoRelease, DatasheetTotalsEqualTheFiles) {
  const std::string readme = ReadFileText((release() / "README.md").string());
  const std::regex totals(std::string(R"(\*\*Totals:\*\* (\d+) trials, (\d+) subjects, (\d+) frames, ([0-9.]+) s \(([0-9.]+) h\))"));
  std::smatch match;
  ASSERT_TRUE(std::regex_search(readme, match, totals)) << readme.substr(0, 2000);
  // Independently: every trials/*/motion.h5 of the release, its time axis read here.
  int64_t frames = 0;
  double seconds = 0;
  size_t trials = 0;
  for (const auto& entry : fs::directory_iterator(release() / "trials")) {
    const MotionData motion = ReadMotionFile((entry.path() / "motion.h5").string());
    frames += motion.frames();
    seconds += motion.time_s.back() - motion.time_s.front();
    ++trials;
  }
  std::set<std::string> subjects;
  for (const ReleaseTrial& trial : ReadReleaseManifest((release() / "manifest.toml").string()).trials) subjects.insert(trial.subject);
  EXPECT_EQ(std::stoul(match[1]), trials);
  EXPECT_EQ(std::stoul(match[2]), subjects.size());
  EXPECT_EQ(std::stoll(match[3]), frames);
  EXPECT_NEAR(std::stod(match[4]), seconds, 0.0005);
  EXPECT_NEAR(std::stod(match[5]), seconds / 3600, 0.00005);
  // The five BVH files' frames, less each dropped T-pose frame and, in 13_11 and 60_10, the three frames that
  // ease in from it (syn-ingest --drop-first-frame).
  EXPECT_EQ(frames, 343 + 1123 + (415 - 3) + 125 + (1197 - 3));
}

TEST_F(DemoRelease, QualityFiguresEqualWhatTheRetargeterLogged) {
  // syn-retarget's own summary line ("median/p95 error P1 24/120 mm 0.245/3.64 deg, P2 nan/nan mm 11.5/39.8 deg")
  // against quality.csv's columns, trial by trial.
  std::istringstream rows(ReadFileText((release() / "quality.csv").string()));
  std::string header;
  std::getline(rows, header);
  int checked = 0;
  for (std::string row; std::getline(rows, row);) {
    std::vector<std::string> cells;
    std::istringstream split(row);
    for (std::string cell; std::getline(split, cell, ',');) cells.push_back(cell);
    ASSERT_EQ(cells.size(), 21u) << row;
    const std::string log = ReadFileText((root_ / "first/outputs/demo/trials" / cells[0] / "motion.h5.log").string());
    std::smatch match;
    ASSERT_TRUE(std::regex_search(log, match, std::regex(R"(P1 ([0-9.]+)/([0-9.]+) mm ([0-9.]+)/([0-9.]+) deg, P2 nan/nan mm ([0-9.]+)/([0-9.]+) deg)")))
        << log;
    const int columns[] = {7, 8, 9, 10, 13, 14};
    for (int i = 0; i < 6; ++i) {
      const double logged = std::stod(match[i + 1]), released = std::stod(cells[static_cast<size_t>(columns[i])]);
      EXPECT_NEAR(released, logged, 0.006 * logged + 0.051) << cells[0] << " column " << columns[i];
    }
    // P2 positions: the G1's priority-2 tasks are orientations only.
    for (int column : {11, 12}) EXPECT_EQ(cells[static_cast<size_t>(column)], "n/a") << row;
    // The feet and floor: "stance drift median/p95/max 45.3/144/144 mm; deepest sole point 30.4 mm below the
    // floor, 34.1 % of frames more than 1 cm below".
    ASSERT_TRUE(std::regex_search(log, match, std::regex(R"(stance drift median/p95/max ([0-9.e+-]+)/([0-9.e+-]+)/[0-9.e+-]+ mm; deepest sole point ([0-9.e+-]+) mm below the floor, ([0-9.e+-]+) % of frames)")))
        << log;
    const int contact_columns[] = {15, 16, 17, 18};
    const double scale[] = {1, 1, 1, 0.01};
    for (int i = 0; i < 4; ++i) {
      const double logged = std::stod(match[i + 1]) * scale[i], released = std::stod(cells[static_cast<size_t>(contact_columns[i])]);
      EXPECT_NEAR(released, logged, 0.006 * logged + (i == 3 ? 0.0051 : 0.051)) << cells[0] << " column " << contact_columns[i];
    }
    EXPECT_EQ(cells[20], "left;right") << row;
    ++checked;
  }
  EXPECT_EQ(checked, 5);
}

TEST_F(DemoRelease, VerifyPassesOnAFreshRelease) {
  const CommandResult on_tar = verify(tar());
  EXPECT_EQ(on_tar.exit_code, 0) << on_tar.output;
  size_t files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(release())) files += entry.is_regular_file();
  EXPECT_NE(on_tar.output.find("verified demo-0.1.0: " + std::to_string(files) + " files, 5 trials"), std::string::npos)
      << on_tar.output;
  const CommandResult on_folder = verify(release().string());
  EXPECT_EQ(on_folder.exit_code, 0) << on_folder.output;
}

TEST_F(DemoRelease, VerifyNamesAMemberWithOneChangedByte) {
  // In the tar itself: one byte of trials/13_11/motion.robot.csv's data.
  const fs::path scratch = root_ / "scratch_members";
  fs::create_directories(scratch);
  uint64_t data_offset = 0;
  for (const TarMember& member : ExtractTar(tar(), scratch.string())) {
    if (member.name == "demo-0.1.0/trials/13_11/motion.robot.csv") data_offset = member.header_offset + 512 + member.size / 2;
  }
  ASSERT_GT(data_offset, 0u);
  const fs::path damaged = root_ / "damaged.tar";
  fs::copy_file(tar(), damaged, fs::copy_options::overwrite_existing);
  {
    std::fstream file(damaged, std::ios::in | std::ios::out | std::ios::binary);
    file.seekg(static_cast<std::streamoff>(data_offset));
    const char byte = static_cast<char>(file.get());
    file.seekp(static_cast<std::streamoff>(data_offset));
    file.put(byte == '7' ? '8' : '7');
  }
  const CommandResult result = verify(damaged.string());
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_NE(result.output.find("demo-0.1.0/trials/13_11/motion.robot.csv: SHA-256"), std::string::npos) << result.output;

  // In a folder: the first byte of a motion file.
  const fs::path folder = copy("one_byte");
  {
    std::fstream file(folder / "trials/60_10/motion.h5", std::ios::in | std::ios::out | std::ios::binary);
    file.put('\x00');
  }
  const CommandResult in_folder = verify(folder.string());
  EXPECT_EQ(in_folder.exit_code, 1) << in_folder.output;
  EXPECT_NE(in_folder.output.find("trials/60_10/motion.h5: SHA-256"), std::string::npos) << in_folder.output;
}

TEST_F(DemoRelease, VerifyNamesARemovedMember) {
  const fs::path folder = copy("removed");
  fs::remove(folder / "trials/05_02/motion.mjlab.npz");
  const CommandResult result = verify(folder.string());
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_NE(result.output.find("trials/05_02/motion.mjlab.npz: listed in SHA256SUMS"), std::string::npos) << result.output;

  // Removed together with its checksum line: the manifest's trial still asks for it.
  std::string sums = ReadFileText((folder / "SHA256SUMS").string());
  const size_t line = sums.find("  trials/05_02/motion.mjlab.npz\n");
  ASSERT_NE(line, std::string::npos);
  sums.erase(line - 64, 64 + std::string("  trials/05_02/motion.mjlab.npz\n").size());
  std::ofstream(folder / "SHA256SUMS", std::ios::binary | std::ios::trunc) << sums;
  const CommandResult unlisted = verify(folder.string());
  EXPECT_EQ(unlisted.exit_code, 1) << unlisted.output;
  EXPECT_NE(unlisted.output.find("trials/05_02/motion.mjlab.npz: missing: manifest.toml line"), std::string::npos)
      << unlisted.output;
}

TEST_F(DemoRelease, VerifyNamesAnEditedDatasheetEvenWithItsChecksumUpdated) {
  const fs::path folder = copy("edited_datasheet");
  std::string readme = ReadFileText((folder / "README.md").string());
  const size_t frames = readme.find(" frames, ");
  ASSERT_NE(frames, std::string::npos);
  readme.replace(frames - 4, 4, "9999");
  std::ofstream(folder / "README.md", std::ios::binary | std::ios::trunc) << readme;
  std::string sums = ReadFileText((folder / "SHA256SUMS").string());
  const size_t line = sums.find("  README.md\n");
  sums.replace(line - 64, 64, Sha256Hex(readme.data(), readme.size()));
  std::ofstream(folder / "SHA256SUMS", std::ios::binary | std::ios::trunc) << sums;
  const CommandResult result = verify(folder.string());
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_NE(result.output.find("demo-0.1.0/README.md: differs from what syn-release makes"), std::string::npos) << result.output;
}

TEST_F(DemoRelease, TwoCleanBuildsGiveTheSameTar) {
  // The second clean tree is built here only (every test runs in its own process).
  const std::string failure = DemoTree(root_ / "second");
  ASSERT_TRUE(failure.empty()) << failure;
  EXPECT_EQ(Sha256OfFile(tar("first")), Sha256OfFile(tar("second")));
}

// The release's bytes against the pipeline re-run from the captures: a member forged together with its
// checksum passes every other check, and --rebuild names it with the byte offset.
TEST_F(DemoRelease, RebuildNamesAForgedMemberAndItsByte) {
  const fs::path folder = copy("forged");
  const fs::path csv = folder / "trials/02_01/motion.unitree.csv";
  std::string text = ReadFileText(csv.string());
  const size_t at = text.find('\n') + 3;  // third character of the second row
  text[at] = text[at] == '1' ? '2' : '1';
  std::ofstream(csv, std::ios::binary | std::ios::trunc) << text;
  std::string sums = ReadFileText((folder / "SHA256SUMS").string());
  const size_t line = sums.find("  trials/02_01/motion.unitree.csv\n");
  sums.replace(line - 64, 64, Sha256Hex(text.data(), text.size()));
  std::ofstream(folder / "SHA256SUMS", std::ios::binary | std::ios::trunc) << sums;
  ASSERT_EQ(verify(folder.string()).exit_code, 0) << "without --rebuild the forgery passes every check";
  const CommandResult result = verify(folder.string(), "--rebuild --source-dir " + (root_ / "first").string());
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_NE(result.output.find("trials/02_01/motion.unitree.csv: differs from the rebuilt release at byte offset " + std::to_string(at)),
            std::string::npos) << result.output;
}

// ---- the parts, on synthetic input --------------------------------------------------------------

TEST(ReleaseTar, LongNamesRoundTripAndUnsafeNamesAreRefused) {
  const fs::path dir = fs::temp_directory_path() / ("syn_tar_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir / "out");
  const std::string long_name = "release-1.0/" + std::string(120, 'a') + "/file.txt";
  {
    TarWriter writer((dir / "a.tar").string());
    writer.addDirectory("release-1.0");
    writer.addBytes(long_name, "hello");
    writer.commit();
  }
  EXPECT_EQ(fs::file_size(dir / "a.tar") % 10240, 0u);
  const std::vector<TarMember> members = ExtractTar((dir / "a.tar").string(), (dir / "out").string());
  ASSERT_EQ(members.size(), 2u);
  EXPECT_EQ(members[1].name, long_name);
  EXPECT_EQ(ReadFileText((dir / "out" / long_name).string()), "hello");
  // GNU tar reads what TarWriter writes.
  const CommandResult listed = RunCommand("tar -tvf " + (dir / "a.tar").string());
  EXPECT_EQ(listed.exit_code, 0) << listed.output;
  EXPECT_NE(listed.output.find(long_name), std::string::npos) << listed.output;

  // A name escaping the folder, made by GNU tar itself.
  std::ofstream(dir / "evil.txt") << "x";
  ASSERT_EQ(RunCommand("cd " + (dir / "out").string() + " && tar --format=gnu -P -cf ../evil.tar ../evil.txt").exit_code, 0);
  try {
    ExtractTar((dir / "evil.tar").string(), (dir / "out").string());
    ADD_FAILURE() << "a '..' member was extracted";
  } catch (const DataError& error) {
    EXPECT_NE(std::string(error.what()).find("unsafe member name"), std::string::npos) << error.what();
  }
  // A damaged header: located at its byte offset.
  std::string bytes = ReadFileText((dir / "a.tar").string());
  bytes[512 + 10] ^= 1;
  std::ofstream(dir / "bad.tar", std::ios::binary) << bytes;
  try {
    ExtractTar((dir / "bad.tar").string(), (dir / "out").string());
    ADD_FAILURE() << "a damaged header was accepted";
  } catch (const DataError& error) {
    EXPECT_EQ(error.where().byte_offset, 512) << error.what();
  }
  fs::remove_all(dir);
}

TEST(ReleaseManifestKeys, ExportAliasesLicencesAndErrors) {
  const std::string base = "name = \"x\"\nlicence = \"CC0\"\n[release]\nexports = [\"lafan1-csv\", \"beyondmimic-npz\", \"mot\"]\n"
                           "[[trial]]\nid = \"a\"\nfile = \"a.bvh\"\n[[trial]]\nid = \"b\"\nfile = \"b.bvh\"\nlicence = \"own\"\n";
  const ReleaseManifest manifest = ParseReleaseManifest(base, "m.toml");
  EXPECT_EQ(manifest.exports, (std::vector<std::string>{"unitree-csv", "mjlab-npz", "mot"}));
  EXPECT_EQ(manifest.trials[0].licence, "CC0");
  EXPECT_EQ(manifest.trials[1].licence, "own");
  EXPECT_EQ(manifest.trials[0].style, "default");
  EXPECT_TRUE(manifest.licenceWarnings().empty());

  const ReleaseManifest unlicensed = ParseReleaseManifest("name = \"x\"\n[[trial]]\nid = \"a\"\n", "m.toml");
  ASSERT_EQ(unlicensed.licenceWarnings().size(), 1u);
  EXPECT_NE(unlicensed.licenceWarnings()[0].find("m.toml:2: trial 'a' names no licence"), std::string::npos)
      << unlicensed.licenceWarnings()[0];
  try {
    static_cast<void>(ParseReleaseManifest("name = \"x\"\n[release]\nexports = [\"fbx\"]\n[[trial]]\nid = \"a\"\n", "m.toml"));
    ADD_FAILURE() << "an unknown export format was accepted";
  } catch (const DataError& error) {
    EXPECT_EQ(error.where().line, 3);
    EXPECT_NE(std::string(error.what()).find("unknown export format 'fbx'"), std::string::npos) << error.what();
  }
}

// The contact figures issue 17 adds to motion.h5 are read as stored, and printed "n/a" when absent.
TEST(TrialQuality, ReadsContactFlagsAndFiguresWhenPresent) {
  const fs::path dir = fs::temp_directory_path() / ("syn_quality_" + std::to_string(::getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  MotionData motion;
  motion.time_s = {0.0, 0.5, 1.0};
  motion.coordinate_names = {"j"};
  motion.velocity_names = {"j"};
  motion.q = motion.u = motion.udot = motion.tau = {0.0, 0.1, 0.2};
  motion.landmark_names = {"left_foot", "upper_torso"};
  motion.landmark_targets.assign(3 * 2 * 7, 0.0);
  // [T, L, 2]: left_foot (priority 1) 1, 2, 3 mm; upper_torso (priority 2) angle 10, 20, 30 degrees.
  motion.landmark_error = {0.001, 0.0, std::nan(""), 10 * M_PI / 180, 0.002, 0.0, std::nan(""), 20 * M_PI / 180,
                           0.003, 0.0, std::nan(""), 30 * M_PI / 180};
  motion.model_name = "m";
  motion.model_sha256 = "0";
  const auto write = [&](const std::string& path, bool with_contact) {
    Provenance provenance;
    provenance.schema = kMotionSchema;
    provenance.schema_version = kMotionSchemaVersion;
    provenance.producer = "release_test";
    IntermediateWriter writer(path, provenance);
    WriteMotionData(writer, motion);
    if (with_contact) {
      writer.writeStrings("contact_feet", {"left", "right"});
      const std::vector<int64_t> flags = {1, 0, 1, 1, 0, 1};
      writer.writeInts("contact", {3, 2}, flags.data());
      writer.writeAttribute("", "stance_drift_median_mm", 3.25);
      writer.writeAttribute("", "stance_drift_p95_mm", 7.5);
      writer.writeAttribute("", "deepest_penetration_mm", 12.0);
      writer.writeAttribute("", "penetration_frames_ratio", 0.125);
    }
    writer.commit();
  };
  write((dir / "with.h5").string(), true);
  write((dir / "without.h5").string(), false);
  std::ofstream(dir / "metrics.json") << R"({"trial": {"foot_sliding_ratio": 0.25}})";
  const std::map<std::string, int> priorities = {{"left_foot", 1}, {"upper_torso", 2}};

  const TrialQuality with = ReadTrialQuality((dir / "with.h5").string(), (dir / "metrics.json").string(), priorities);
  EXPECT_EQ(with.frames, 3);
  EXPECT_DOUBLE_EQ(with.duration_s, 1.0);
  EXPECT_DOUBLE_EQ(with.rate_hz, 2.0);
  EXPECT_NEAR(with.p1_position_median_mm, 2.0, 1e-9);
  EXPECT_NEAR(with.p1_position_p95_mm, 3.0, 1e-9);  // nearest rank round(0.95 * 2) = 2
  EXPECT_NEAR(with.p2_angle_median_deg, 20.0, 1e-9);
  EXPECT_TRUE(std::isnan(with.p2_position_median_mm));
  EXPECT_DOUBLE_EQ(with.stance_drift_median_mm, 3.25);
  EXPECT_DOUBLE_EQ(with.stance_drift_p95_mm, 7.5);
  EXPECT_DOUBLE_EQ(with.deepest_penetration_mm, 12.0);
  EXPECT_DOUBLE_EQ(with.penetration_frames_ratio, 0.125);
  EXPECT_EQ(with.contact_feet, (std::vector<std::string>{"left", "right"}));
  EXPECT_DOUBLE_EQ(with.foot_sliding_ratio, 0.25);
  EXPECT_EQ(ContactFlagsCsv((dir / "with.h5").string()), "time,left,right\n0,1,0\n0.5,1,1\n1,0,1\n");

  const TrialQuality without = ReadTrialQuality((dir / "without.h5").string(), (dir / "metrics.json").string(), priorities);
  EXPECT_EQ(FigureText(without.stance_drift_p95_mm, 1), "n/a");
  EXPECT_EQ(FigureText(without.penetration_frames_ratio, 4), "n/a");
  EXPECT_TRUE(without.contact_feet.empty());
  EXPECT_EQ(ContactFlagsCsv((dir / "without.h5").string()), "");
  EXPECT_EQ(FigureText(-0.01, 1), "0.0");
  fs::remove_all(dir);
}

}  // namespace
}  // namespace syn::testing
