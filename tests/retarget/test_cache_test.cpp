// The tests' cache of retargeted motions (tests/support/demo_motion.h): a second call gives back exactly
// what the first computed, and an edited capture is computed afresh, not served the old motion.
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "tests/support/demo_motion.h"
#include "tests/support/scratch_file.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

namespace fs = std::filesystem;

// The demo's 02_01 cut to its first `frames` frames, its root moved `shift` (the file's units) along X in the
// last one.
void WriteShortWalk(const fs::path& path, int frames, double shift) {
  std::ifstream in(testing::SourcePath("datasets/demo/02_01.bvh"));
  std::ofstream out(path);
  std::string line;
  int motion_line = -1;
  while (std::getline(in, line)) {
    if (line.rfind("Frames:", 0) == 0) {
      out << "Frames: " << frames << "\n";
      continue;
    }
    if (line.rfind("Frame Time:", 0) == 0) {
      out << line << "\n";
      motion_line = 0;
      continue;
    }
    if (motion_line >= 0) {
      if (motion_line == frames) break;
      if (++motion_line == frames && shift != 0) {
        std::istringstream values(line);
        double x = 0;
        values >> x;
        std::string rest;
        std::getline(values, rest);
        out << x + shift << rest << "\n";
        continue;
      }
    }
    out << line << "\n";
  }
}

TEST(RetargetTestCache, GivesBackWhatItComputedAndMissesAnEditedCapture) {
  const fs::path dir = testing::ProcessScratchDir("syn_test_cache_");
  // A name of this process's own: the cache names its entries by the capture's stem, and these are removed
  // at the end.
  const std::string stem = "short_walk_" + std::to_string(::getpid());
  const fs::path walk = dir / (stem + ".bvh");
  WriteShortWalk(walk, 100, 0.0);
  const MotionData computed = testing::CmuBvhOnG1(walk.string());
  const MotionData cached = testing::CmuBvhOnG1(walk.string());
  ASSERT_GT(computed.frames(), 90);
  EXPECT_TRUE(testing::SameBits(computed.q, cached.q));
  EXPECT_TRUE(testing::SameBits(computed.tau, cached.tau));
  EXPECT_EQ(computed.contact, cached.contact);

  // The same file name, its last frame's root 2 units further along X (after the ingest's 0.5 s lead-in
  // checks, and slower than a teleport): computed afresh.
  WriteShortWalk(walk, 100, 2.0);
  const MotionData edited = testing::CmuBvhOnG1(walk.string());
  ASSERT_EQ(edited.frames(), computed.frames());
  EXPECT_FALSE(testing::SameBits(edited.q, computed.q)) << "the edited capture was served the cached motion";
  int entries = 0;
  for (const fs::directory_entry& entry : fs::directory_iterator(SYN_TEST_CACHE_DIR)) {
    if (entry.path().filename().string().rfind(stem + "-", 0) == 0) fs::remove(entry.path()), ++entries;
  }
  EXPECT_EQ(entries, 2) << "one cache entry per capture";
}

}  // namespace
}  // namespace syn
