// What `syn-retarget -v` lists for a user to look at first: the frames where a landmark is furthest from its
// target (by position and by angle), checked against the landmark errors the motion file itself holds.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <regex>
#include <string>
#include <vector>

#include "common/motion_file.h"
#include "tests/support/demo_motion.h"
#include "tests/support/run_command.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

struct Listed {
  int64_t frame = -1;
  std::string landmark;
  double value = 0;  // mm or deg, as printed
};

std::vector<Listed> ListedWorst(const std::string& log, const std::string& part) {
  std::vector<Listed> listed;
  const std::regex line("syn-retarget: worst " + part + R"( error #\d+: frame (\d+) \(t = [0-9.e+-]+ s\), (\S+) ([0-9.e+-]+) (mm|deg))");
  for (auto it = std::sregex_iterator(log.begin(), log.end(), line); it != std::sregex_iterator(); ++it) {
    listed.push_back({std::stoll((*it)[1]), (*it)[2], std::stod((*it)[3])});
  }
  return listed;
}

TEST(RetargetVerbose, ListsTheWorstFramesTheMotionFileHolds) {
  const std::string dir = std::filesystem::temp_directory_path() / ("syn_retarget_verbose_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  const std::string markers = dir + "/walk.markers.h5", motion_path = dir + "/walk.motion.h5";
  const testing::CommandResult ingest = testing::RunCommand(testing::BinPath("syn-ingest") + " " + testing::SourcePath("datasets/demo/02_01.bvh") +
                                          " --drop-first-frame -o " + markers);
  ASSERT_EQ(ingest.exit_code, 0) << ingest.output;
  const testing::CommandResult run = testing::RunCommand(testing::BinPath("syn-retarget") + " " + markers + " -o " + motion_path + " --model " +
                                       testing::SourcePath(testing::kG1Urdf) + " --robot-map " +
                                       testing::SourcePath(testing::kG1Map) + " --markerset " +
                                       testing::SourcePath("manifests/markersets/cmu-bvh.toml") + " -v");
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const MotionData motion = ReadMotionFile(motion_path);
  std::filesystem::remove_all(dir);
  const size_t landmarks = motion.landmark_names.size(), frames = static_cast<size_t>(motion.frames());
  ASSERT_GT(landmarks, 0u);
  for (const int part : {0, 1}) {
    const std::vector<Listed> listed = ListedWorst(run.output, part == 0 ? "position" : "angle");
    ASSERT_EQ(listed.size(), 5u) << run.output;
    // The file's worst frame, computed here from its landmark_error [T, L, 2].
    double file_worst = -1;
    for (size_t t = 0; t < frames; ++t) {
      for (size_t l = 0; l < landmarks; ++l) {
        const double e = motion.landmark_error[(t * landmarks + l) * 2 + static_cast<size_t>(part)];
        if (std::isfinite(e)) file_worst = std::max(file_worst, e);
      }
    }
    const double unit = part == 0 ? 1000.0 : 180.0 / M_PI;
    EXPECT_NEAR(listed[0].value, file_worst * unit, 1e-3 * file_worst * unit);
    for (size_t k = 0; k < listed.size(); ++k) {
      const Listed& entry = listed[k];
      ASSERT_GE(entry.frame, 0);
      ASSERT_LT(static_cast<size_t>(entry.frame), frames);
      size_t l = 0;
      while (l < landmarks && motion.landmark_names[l] != entry.landmark) ++l;
      ASSERT_LT(l, landmarks) << entry.landmark;
      const double e = motion.landmark_error[(static_cast<size_t>(entry.frame) * landmarks + l) * 2 + static_cast<size_t>(part)];
      EXPECT_NEAR(entry.value, e * unit, 1e-3 * e * unit) << "entry " << k + 1;
      if (k > 0) {
        EXPECT_LE(entry.value, listed[k - 1].value) << "listed from the worst down";
        for (size_t j = 0; j < k; ++j) {
          EXPECT_GE(std::abs(motion.time_s[static_cast<size_t>(entry.frame)] - motion.time_s[static_cast<size_t>(listed[j].frame)]), 0.25)
              << "entries " << j + 1 << " and " << k + 1 << " are one stretch";
        }
      }
    }
  }
}

}  // namespace
}  // namespace syn
