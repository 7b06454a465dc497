// One trial written by different processors must read identically: the SGI (MIPS, big-endian) copies
// made from every PC (Intel) C3D in ../shared by an independent byte-swapping script
// (tests/ingest/c3d_to_mips.py), and c3d.org's own Intel / DEC / MIPS copies of sample01 — compared
// field by field: every parameter's type, dimensions, values, strings, lock flag and description, and
// every decoded sample.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>

#include "common/error.h"
#include "common/file_bytes.h"
#include "stages/ingest/c3d_reader.h"
#include "tests/support/run_command.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

namespace fs = std::filesystem;

bool IsIntel(const std::vector<uint8_t>& bytes) {
  if (bytes.size() < 512) return false;
  const size_t start = bytes[0] >= 2 ? (bytes[0] - 1) * 512u : 0;
  return start >= 512 && start + 4 <= bytes.size() && bytes[start + 3] == 84;
}

// Equal, NaN equal to NaN; `relative` tolerance for DEC's VAX floats (exact otherwise).
bool Same(double a, double b, double relative) {
  if (std::isnan(a) || std::isnan(b)) return std::isnan(a) && std::isnan(b);
  return std::abs(a - b) <= relative * std::max(std::abs(a), std::abs(b));
}

void ExpectSameParameters(const std::vector<C3dParameter>& expected, const std::vector<C3dParameter>& got,
                          double relative) {
  ASSERT_EQ(got.size(), expected.size());
  for (size_t i = 0; i < expected.size(); ++i) {
    SCOPED_TRACE(expected[i].key);
    ASSERT_EQ(got[i].key, expected[i].key);
    EXPECT_EQ(got[i].type, expected[i].type);
    EXPECT_EQ(got[i].dimensions, expected[i].dimensions);
    EXPECT_EQ(got[i].strings, expected[i].strings);
    EXPECT_EQ(got[i].locked, expected[i].locked);
    EXPECT_EQ(got[i].description, expected[i].description);
    ASSERT_EQ(got[i].numbers.size(), expected[i].numbers.size());
    const double tolerance = expected[i].type == 4 ? relative : 0.0;
    for (size_t k = 0; k < expected[i].numbers.size(); ++k) {
      EXPECT_TRUE(Same(got[i].numbers[k], expected[i].numbers[k], tolerance))
          << "value " << k << ": " << got[i].numbers[k] << " vs " << expected[i].numbers[k];
    }
  }
}

void ExpectSameValues(const std::vector<double>& expected, const std::vector<double>& got, const char* what) {
  ASSERT_EQ(got.size(), expected.size()) << what;
  size_t different = 0;
  for (size_t i = 0; i < expected.size(); ++i) different += !Same(got[i], expected[i], 0.0);
  EXPECT_EQ(different, 0u) << what;
}

TEST(C3dProcessors, MipsCopiesOfEveryIntelFileReadIdentically) {
  SYN_REQUIRE_SHARED("c3d");
  if (testing::RunCommand("python3 --version").exit_code != 0) GTEST_SKIP() << "python3 absent: cannot build MIPS copies";
  const fs::path folder = fs::temp_directory_path() / ("syn_mips_" + std::to_string(::getpid()));
  fs::create_directories(folder);
  const std::string script = testing::SourcePath("tests/ingest/c3d_to_mips.py");
  int compared = 0, damaged = 0;
  for (const auto& entry : fs::recursive_directory_iterator(testing::SharedPath("c3d"))) {
    std::string extension = entry.path().extension().string();
    for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
    if (extension != ".c3d") continue;
    const std::vector<uint8_t> intel = ReadFileBytes(entry.path().string());
    if (!IsIntel(intel)) continue;
    SCOPED_TRACE(entry.path().string());
    const std::string mips_path = (folder / ("mips_" + std::to_string(compared) + ".c3d")).string();
    const testing::CommandResult swap = testing::RunCommand("python3 '" + script + "' '" + entry.path().string() + "' '" + mips_path + "'");
    // Files whose parameter records overlap (damaged 'offset to next') cannot be byte-swapped record by
    // record: one byte would be both a number to swap and a character to keep. The script says so (3).
    if (swap.exit_code == 3) {
      ++damaged;
      continue;
    }
    ASSERT_EQ(swap.exit_code, 0) << swap.output;
    const std::vector<uint8_t> mips = ReadFileBytes(mips_path);
    ASSERT_EQ(mips.size(), intel.size());
    ++compared;

    MarkerData from_intel, from_mips;
    std::string intel_error, mips_error;
    try {
      from_intel = ParseC3d(intel.data(), intel.size(), "same.c3d");
    } catch (const DataError& error) {
      intel_error = error.what();
    }
    try {
      from_mips = ParseC3d(mips.data(), mips.size(), "same.c3d");
    } catch (const DataError& error) {
      mips_error = error.what();
    }
    ASSERT_EQ(mips_error, intel_error);
    if (!intel_error.empty()) continue;
    ExpectSameParameters(ParseC3dParameters(intel.data(), intel.size(), "intel"),
                         ParseC3dParameters(mips.data(), mips.size(), "mips"), 0.0);
    EXPECT_EQ(from_mips.labels, from_intel.labels);
    EXPECT_EQ(from_mips.computed_labels, from_intel.computed_labels);
    EXPECT_EQ(from_mips.analog_labels, from_intel.analog_labels);
    EXPECT_EQ(from_mips.analog_units, from_intel.analog_units);
    EXPECT_EQ(from_mips.bodies, from_intel.bodies);
    EXPECT_EQ(from_mips.rate_hz, from_intel.rate_hz);
    EXPECT_EQ(from_mips.analog_rate_hz, from_intel.analog_rate_hz);
    EXPECT_EQ(from_mips.length_unit_to_m, from_intel.length_unit_to_m);
    EXPECT_EQ(from_mips.up_axis, from_intel.up_axis);
    EXPECT_EQ(from_mips.warnings, from_intel.warnings);
    ExpectSameValues(from_intel.time_s, from_mips.time_s, "time");
    ExpectSameValues(from_intel.points, from_mips.points, "points");
    ExpectSameValues(from_intel.computed_points, from_mips.computed_points, "computed points");
    ExpectSameValues(from_intel.analog, from_mips.analog, "analog");
    ExpectSameValues(from_intel.body_pose, from_mips.body_pose, "body poses");
    ASSERT_EQ(from_mips.events.size(), from_intel.events.size());
    for (size_t e = 0; e < from_intel.events.size(); ++e) {
      EXPECT_EQ(from_mips.events[e].label, from_intel.events[e].label);
      EXPECT_EQ(from_mips.events[e].time_s, from_intel.events[e].time_s);
    }
    nlohmann::json intel_meta = from_intel.metadata, mips_meta = from_mips.metadata;
    EXPECT_EQ(mips_meta["c3d"]["processor"], "mips");
    intel_meta["c3d"].erase("processor");
    mips_meta["c3d"].erase("processor");
    EXPECT_EQ(mips_meta, intel_meta);
  }
  fs::remove_all(folder);
  EXPECT_GE(compared, 25);  // SOURCES.md lists 29 Intel files
  EXPECT_LE(damaged, 2);     // btk_others/badParameterOffset.c3d, c3d_org/sample18/bad_parameter_section.c3d
}

// c3d.org sample01: one gait trial written by a PC, a VAX and an SGI machine, as int16 and as floats.
TEST(C3dProcessors, C3dOrgIntelDecAndMipsCopiesHaveTheSameParameters) {
  SYN_REQUIRE_SHARED("c3d/c3d_org/sample01");
  for (const char* storage : {"i", "r"}) {
    SCOPED_TRACE(storage);
    const auto read = [&](const char* processor) {
      const std::vector<uint8_t> bytes =
          ReadFileBytes(testing::SharedPath(std::string("c3d/c3d_org/sample01/Eb015") + processor + storage + ".c3d"));
      return ParseC3dParameters(bytes.data(), bytes.size(), processor);
    };
    const std::vector<C3dParameter> intel = read("p");
    ASSERT_GT(intel.size(), 40u);  // 42 groups and parameters
    {
      SCOPED_TRACE("MIPS");
      ExpectSameParameters(intel, read("s"), 0.0);
    }
    {
      SCOPED_TRACE("DEC");
      // VAX F-floats carry the same 24-bit mantissa; the conversion through IEEE may round the last bit.
      ExpectSameParameters(intel, read("v"), 1e-6);
    }
  }
}

}  // namespace
}  // namespace syn
