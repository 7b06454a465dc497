#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <algorithm>
#include <filesystem>
#include <set>

#include <Eigen/Core>

#include "common/file_bytes.h"
#include "tools/archive/archive_generator.h"
#include "stages/ingest/ingest.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

namespace fs = std::filesystem;

std::vector<SourceTrial> Sources() {
  std::vector<SourceTrial> sources;
  for (const char* id : {"02_01", "05_02", "13_11"}) {
    SourceTrial source;
    source.id = id;
    source.path = testing::SharedPath(std::string("cmu_bvh/") + std::string(id).substr(0, 2) + "/" + id + ".bvh");
    source.motion_class = std::string("x");
    source.style = source.motion_class;
    sources.push_back(source);
  }
  return sources;
}

std::string Directory(const std::string& name) {
  return fs::temp_directory_path() / ("syn_archive_" + name + "_" + std::to_string(::getpid()));
}

TEST(ArchiveGenerator, IsSeededFillsTheRequestedTimeAndItsGapsFill) {
  SYN_REQUIRE_SHARED("cmu_bvh/05/05_02.bvh");
  ArchiveOptions options;
  options.subjects = 2;
  options.hours = 60.0 / 3600;  // 30 s per subject
  const std::string first = Directory("a"), second = Directory("b");
  const std::vector<GeneratedTrial> trials = GenerateArchive(Sources(), first, options, nullptr);
  (void)GenerateArchive(Sources(), second, options, nullptr);
  double per_subject[2] = {0, 0};
  for (const GeneratedTrial& trial : trials) {
    EXPECT_EQ(ReadFileText(first + "/captures/" + trial.file), ReadFileText(second + "/captures/" + trial.file)) << trial.file;
    per_subject[trial.subject == "s01" ? 0 : 1] += static_cast<double>(trial.frames) / options.rate;
  }
  EXPECT_NEAR(per_subject[0], 30.0, 1.0 / options.rate);
  EXPECT_NEAR(per_subject[1], 30.0, 1.0 / options.rate);

  // Every gap is interior and short enough for --fill-gaps 30.
  IngestOptions ingest;
  ingest.up_axis = "z";
  ingest.fill_gaps = 30;
  IngestSummary summary;
  const MarkerData capture = IngestCapture(first + "/captures/" + trials.front().file, ingest, &summary);
  EXPECT_EQ(capture.marker_count(), 22);
  int64_t filled = 0, left = 0;
  for (const MarkerGapReport& report : summary.gaps) {
    filled += report.gaps_filled;
    left += report.missing_after;
  }
  EXPECT_GT(filled, 0);
  EXPECT_EQ(left, 0);
  fs::remove_all(first);
  fs::remove_all(second);
}

TEST(ArchiveGenerator, MarkerNoiseHasTheRequestedSpread) {
  SYN_REQUIRE_SHARED("cmu_bvh/05/05_02.bvh");
  ArchiveOptions options;
  options.subjects = 1;
  options.hours = 20.0 / 3600;
  options.gaps_per_second = 0;
  const std::string quiet = Directory("quiet"), noisy = Directory("noisy");
  options.noise_mm = 0;
  const std::vector<GeneratedTrial> trials = GenerateArchive(Sources(), quiet, options, nullptr);
  options.noise_mm = 2.0;
  (void)GenerateArchive(Sources(), noisy, options, nullptr);
  IngestOptions ingest;
  ingest.up_axis = "z";
  // The same draws position both archives (noise only scales them), so their difference is the noise alone.
  const MarkerData a = IngestCapture(quiet + "/captures/" + trials.front().file, ingest, nullptr);
  const MarkerData b = IngestCapture(noisy + "/captures/" + trials.front().file, ingest, nullptr);
  ASSERT_EQ(a.points.size(), b.points.size());
  double sum = 0, squares = 0;
  for (size_t i = 0; i < a.points.size(); ++i) {
    const double d = 1000.0 * (b.points[i] - a.points[i]);
    sum += d;
    squares += d * d;
  }
  const double n = static_cast<double>(a.points.size());
  EXPECT_NEAR(sum / n, 0.0, 0.05);
  EXPECT_NEAR(std::sqrt(squares / n), 2.0, 0.1);
  fs::remove_all(quiet);
  fs::remove_all(noisy);
}

// One trial of each cgspeed convention (mb2 02_01, Daz 10_01, 3dsMax 14_14 excerpt) is used, and its
// joint markers sit on one rigid skeleton: a bone joins two real joints only if the name table maps
// each SMPL joint to the right BVH joint, so its length barely changes (noise 1 mm, no gaps here).
TEST(ArchiveGenerator, EveryCmuConventionGivesRigidBones) {
  SYN_REQUIRE_SHARED("cmu_bvh/10/10_01.bvh");
  std::vector<SourceTrial> sources;
  for (const char* path : {"02/02_01.bvh", "10/10_01.bvh", "14/14_14_excerpt.bvh"}) {
    SourceTrial source;
    source.path = testing::SharedPath(std::string("cmu_bvh/") + path);
    source.id = fs::path(path).stem().string();
    source.motion_class = source.style = "x";
    sources.push_back(source);
  }
  ArchiveOptions options;
  options.subjects = 1;
  options.hours = 30.0 / 3600;
  options.gaps_per_second = 0;
  const std::string directory = Directory("conventions");
  std::vector<std::string> skipped;
  const std::vector<GeneratedTrial> trials = GenerateArchive(sources, directory, options, &skipped);
  EXPECT_TRUE(skipped.empty()) << skipped.front();
  std::set<std::string> used;
  const std::pair<const char*, const char*> bones[] = {{"left_hip", "left_knee"},     {"left_knee", "left_ankle"},
                                                       {"right_knee", "right_ankle"}, {"left_shoulder", "left_elbow"},
                                                       {"left_elbow", "left_wrist"},  {"right_elbow", "right_wrist"},
                                                       {"pelvis", "head"}};
  IngestOptions ingest;
  ingest.up_axis = "z";
  for (const GeneratedTrial& trial : trials) {
    used.insert(trial.source);
    const MarkerData capture = IngestCapture(directory + "/captures/" + trial.file, ingest, nullptr);
    const int64_t markers = capture.marker_count();
    auto index = [&](const char* label) {
      return std::find(capture.labels.begin(), capture.labels.end(), label) - capture.labels.begin();
    };
    for (const auto& [from, to] : bones) {
      const int64_t a = index(from), b = index(to);
      ASSERT_LT(b, markers) << to;
      double sum = 0, squares = 0;
      for (int64_t t = 0; t < capture.frame_count(); ++t) {
        const Eigen::Map<const Eigen::Vector3d> pa(&capture.points[static_cast<size_t>((t * markers + a) * 3)]);
        const Eigen::Map<const Eigen::Vector3d> pb(&capture.points[static_cast<size_t>((t * markers + b) * 3)]);
        const double length = (pa - pb).norm();
        sum += length, squares += length * length;
      }
      const double n = static_cast<double>(capture.frame_count()), mean = sum / n;
      EXPECT_GT(mean, 0.1) << trial.source << " " << from << "-" << to;
      EXPECT_LT(std::sqrt(std::max(0.0, squares / n - mean * mean)), 0.01) << trial.source << " " << from << "-" << to;
    }
  }
  EXPECT_EQ(used.size(), 3u);
  fs::remove_all(directory);
}

}  // namespace
}  // namespace syn

namespace syn {
namespace {

TEST(ArchiveGenerator, ManifestRunsThePapersProtocolUnlessAskedForThroughput) {
  const std::vector<GeneratedTrial> trials = {{"s01_walk", "s01", "captures/s01_walk.trc", "walk", "walk", "02_01", 10.0, 1200, false}};
  ArchiveOptions options;
  const std::string paper = ArchiveManifest(trials, "captures", options);
  EXPECT_NE(paper.find("[evaluate]\neval_rate = 1000\nsamples = 100\n"), std::string::npos) << paper;
  options.paper_protocol = false;
  const std::string throughput = ArchiveManifest(trials, "captures", options);
  EXPECT_NE(throughput.find("[evaluate]\neval_rate = 120\nsamples = 0\n"), std::string::npos) << throughput;
}

}  // namespace
}  // namespace syn
