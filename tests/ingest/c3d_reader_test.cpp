// The C3D reader against ezc3d's readings of every shared C3D file, against
// itself across processor/storage variants, and under damage.
#include "stages/ingest/c3d_reader.h"

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include <Eigen/Geometry>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <map>

#include "common/error.h"
#include "common/file_bytes.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> ReferenceFiles() {
  std::vector<std::string> files;
  const std::string folder = testing::SharedPath("c3d/ezc3d_reference");
  if (!fs::exists(folder)) return files;
  for (const auto& entry : fs::recursive_directory_iterator(folder)) {
    const std::string name = entry.path().filename().string();
    if (name.size() > 9 && name.compare(name.size() - 9, 9, ".c3d.json") == 0 && name.rfind("lenient_", 0) != 0) {
      files.push_back(entry.path().string());
    }
  }
  std::sort(files.begin(), files.end());
  return files;
}

// Where original point `index` landed in our reading: a marker slot or a computed slot.
struct Slot {
  bool computed = false;
  size_t index = 0;
};

std::vector<Slot> SlotsOf(const MarkerData& data, const std::vector<std::string>& original_labels, size_t points) {
  std::vector<Slot> slots(points);
  size_t marker = 0, computed = 0;
  for (size_t i = 0; i < points; ++i) {
    const std::string label = i < original_labels.size() ? original_labels[i] : "";
    if (computed < data.computed_labels.size() && data.computed_labels[computed] == label &&
        (marker >= data.labels.size() || data.labels[marker] != label)) {
      slots[i] = {true, computed++};
    } else {
      slots[i] = {false, marker++};
    }
  }
  return slots;
}

TEST(C3dReader, MatchesEzc3dWhereverEzc3dReadsTheFile) {
  SYN_REQUIRE_SHARED("c3d/ezc3d_reference");
  const auto references = ReferenceFiles();
  ASSERT_GE(references.size(), 30u);
  int compared = 0;
  for (const std::string& reference_path : references) {
    std::ifstream in(reference_path);
    const nlohmann::json reference = nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/false);
    if (reference.is_discarded() || !reference.value("ok", false)) continue;  // ezc3d failed on that file
    const std::string relative = reference["file"].get<std::string>();  // "c3d/...."
    SCOPED_TRACE(relative);
    const MarkerData data = ReadC3d(testing::SharedPath(relative));
    ++compared;
    const size_t points = reference["nb_points_data"].get<size_t>();
    if (points == 0 && reference["raw_header"]["nb_points"].get<size_t>() > 0) {
      // ezc3d found no points where the header declares some (sample20 has no parameter section): not a
      // reading to compare with; PhasespaceWithoutParameters checks ours.
      continue;
    }
    EXPECT_EQ(data.frame_count(), reference["nb_frames"].get<int64_t>());
    EXPECT_EQ(data.labels.size() + data.computed_labels.size(), points);
    std::vector<std::string> names;
    for (const auto& name : reference["point_names"]) names.push_back(name.get<std::string>());
    names.resize(points);
    const std::vector<Slot> slots = SlotsOf(data, names, points);
    for (size_t i = 0; i < points; ++i) {
      const std::string ours = slots[i].computed ? data.computed_labels[slots[i].index] : data.labels[slots[i].index];
      if (!names[i].empty()) {
        EXPECT_EQ(ours, names[i]) << "point " << i;
      }
    }
    // Sampled coordinates, in the file's own units.
    const size_t markers = data.labels.size(), computed = data.computed_labels.size();
    for (const auto& point : reference["points"]) {
      const size_t index = point["index"].get<size_t>();
      if (index >= points) continue;
      const Slot slot = slots[index];
      int64_t our_missing = 0;
      for (int64_t t = 0; t < data.frame_count(); ++t) {
        const double* xyz = slot.computed ? &data.computed_points[(static_cast<size_t>(t) * computed + slot.index) * 3]
                                          : &data.points[(static_cast<size_t>(t) * markers + slot.index) * 3];
        our_missing += std::isnan(xyz[0]);
      }
      // ezc3d calls only a negative residual invalid; we also drop exact (0, 0, 0) samples (vendor gap convention).
      EXPECT_GE(our_missing, point["n_invalid"].get<int64_t>()) << point["label"];
      EXPECT_LE(our_missing, point["n_invalid"].get<int64_t>() + point["n_all_zero"].get<int64_t>()) << point["label"];
      for (const auto& sample : point["samples"]) {
        const int64_t frame = sample["frame"].get<int64_t>();
        if (frame >= data.frame_count()) continue;
        const double* xyz = slot.computed ? &data.computed_points[(static_cast<size_t>(frame) * computed + slot.index) * 3]
                                          : &data.points[(static_cast<size_t>(frame) * markers + slot.index) * 3];
        if (sample["x"].is_null()) {
          EXPECT_TRUE(std::isnan(xyz[0])) << point["label"] << " frame " << frame;
          continue;
        }
        const double x = sample["x"].get<double>(), y = sample["y"].get<double>(), z = sample["z"].get<double>();
        if (x == 0 && y == 0 && z == 0) {
          EXPECT_TRUE(std::isnan(xyz[0]));
          continue;
        }
        const double tolerance = 1e-6 * (1 + std::abs(x) + std::abs(y) + std::abs(z));
        EXPECT_NEAR(xyz[0], x, tolerance) << point["label"] << " frame " << frame;
        EXPECT_NEAR(xyz[1], y, tolerance) << point["label"] << " frame " << frame;
        EXPECT_NEAR(xyz[2], z, tolerance) << point["label"] << " frame " << frame;
      }
    }
    // Checksum over all valid samples (zeros add nothing, so our stricter rule does not change it).
    double sum = 0;
    for (double value : data.points) sum += std::isnan(value) ? 0 : value;
    for (double value : data.computed_points) sum += std::isnan(value) ? 0 : value;
    const double expected_sum = reference["checksum_valid_xyz_sum"].get<double>();
    EXPECT_NEAR(sum, expected_sum, 1e-6 * (1 + std::abs(expected_sum)));
    // ezc3d read a single analog subframe per frame of Kistler.c3d (no points, 10 subframes at 600 Hz): where
    // its value count disagrees with the file's layout, check the layout against ANALOG:RATE instead.
    const bool same_analog_count = reference.contains("n_analog_values") &&
                                   reference["n_analog_values"].get<size_t>() == data.analog.size();
    if (!same_analog_count && reference.contains("ANALOG:RATE") && reference["analog_channels"].get<int>() > 0) {
      EXPECT_NEAR(data.analog_rate_hz, reference["ANALOG:RATE"]["values"][0].get<double>(), 1e-3);
    }
    if (reference.contains("analog_sum") && reference["analog_channels"].get<int>() > 0 && same_analog_count) {
      double analog = 0;
      for (double value : data.analog) analog += value;
      const double expected = reference["analog_sum"].get<double>();
      EXPECT_NEAR(analog, expected, 1e-6 * (1 + std::abs(expected))) << "analog";
    }
  }
  EXPECT_GE(compared, 25);
}

TEST(C3dReader, SixProcessorAndStorageVariantsAgree) {
  SYN_REQUIRE_SHARED("c3d/c3d_org/sample01/Eb015pr.c3d");
  const MarkerData reference = ReadC3d(testing::SharedPath("c3d/c3d_org/sample01/Eb015pr.c3d"));
  const double half_step = 0.5 * std::abs(reference.metadata["c3d"]["scale"].get<double>());
  for (const char* variant : {"Eb015pi", "Eb015si", "Eb015sr", "Eb015vi", "Eb015vr"}) {
    SCOPED_TRACE(variant);
    const MarkerData data = ReadC3d(testing::SharedPath(std::string("c3d/c3d_org/sample01/") + variant + ".c3d"));
    ASSERT_EQ(data.points.size(), reference.points.size());
    ASSERT_EQ(data.labels, reference.labels);
    const bool integer = std::string(variant).back() == 'i';
    // Integer files were written from the same data rounded to the scale step (0.083 mm here).
    const double tolerance = integer ? half_step * 1.0001 + 1e-9 : 1e-4;
    double worst = 0;
    for (size_t i = 0; i < data.points.size(); ++i) {
      ASSERT_EQ(std::isnan(data.points[i]), std::isnan(reference.points[i])) << i;
      if (!std::isnan(data.points[i])) worst = std::max(worst, std::abs(data.points[i] - reference.points[i]));
    }
    EXPECT_LE(worst, tolerance);
    ASSERT_EQ(data.analog.size(), reference.analog.size());
    // The header's event section decodes the same on every processor (3 events at 2.72, 5.40, 7.32 s).
    ASSERT_EQ(data.events.size(), 3u);
    for (size_t e = 0; e < 3; ++e) EXPECT_NEAR(data.events[e].time_s, reference.events[e].time_s, 1e-6);
  }
  ASSERT_EQ(reference.events.size(), 3u);
  EXPECT_NEAR(reference.events[0].time_s, 2.72, 1e-6);
}

TEST(C3dReader, EverySharedFileReadsOrIsRefusedWithALocation) {
  SYN_REQUIRE_SHARED("c3d");
  int files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(testing::SharedPath("c3d"))) {
    std::string extension = entry.path().extension().string();
    std::transform(extension.begin(), extension.end(), extension.begin(), ::tolower);
    if (extension != ".c3d") continue;
    ++files;
    try {
      const MarkerData data = ReadC3d(entry.path().string());
      EXPECT_EQ(data.time_s.size() * data.labels.size() * 3, data.points.size()) << entry.path();
    } catch (const DataError& error) {
      EXPECT_NE(std::string(error.what()).find("byte offset"), std::string::npos) << error.what();
    }
  }
  EXPECT_GE(files, 40);
}

TEST(C3dReader, PhasespaceWithoutParametersFallsBackToTheHeader) {
  SYN_REQUIRE_SHARED("c3d/c3d_org/sample20/phasespace_sample.c3d");
  const MarkerData data = ReadC3d(testing::SharedPath("c3d/c3d_org/sample20/phasespace_sample.c3d"));
  // SOURCES.md: 40 points, 30 Hz, 701 frames, float storage, no parameter section.
  EXPECT_EQ(data.labels.size(), 40u);
  EXPECT_EQ(data.frame_count(), 701);
  EXPECT_DOUBLE_EQ(data.rate_hz, 30.0);
  // Plausible human-scale coordinates (mm): the stride and storage were right.
  double largest = 0;
  for (double value : data.points) largest = std::isnan(value) ? largest : std::max(largest, std::abs(value));
  EXPECT_GT(largest, 100.0);
  EXPECT_LT(largest, 1e5);
}

TEST(C3dReader, TruncatedOptotrakReadsTheFramesPresent) {
  SYN_REQUIRE_SHARED("c3d/ezc3d/Optotrak.c3d");
  const MarkerData data = ReadC3d(testing::SharedPath("c3d/ezc3d/Optotrak.c3d"));
  EXPECT_EQ(data.frame_count(), 29);
  bool warned = false;
  for (const std::string& warning : data.warnings) warned = warned || warning.find("truncated") != std::string::npos;
  EXPECT_TRUE(warned);
}

TEST(C3dReader, QualisysGapsAreMissingNotZero) {
  SYN_REQUIRE_SHARED("c3d/numediart/03_rolling.c3d");
  const MarkerData data = ReadC3d(testing::SharedPath("c3d/numediart/03_rolling.c3d"));
  size_t missing = 0, zeros = 0;
  for (size_t i = 0; i + 2 < data.points.size(); i += 3) {
    missing += std::isnan(data.points[i]);
    zeros += data.points[i] == 0 && data.points[i + 1] == 0 && data.points[i + 2] == 0;
  }
  EXPECT_GT(missing, 0u);
  EXPECT_EQ(zeros, 0u);
}

bool SameValues(const double* a, const double* b, size_t count) {
  for (size_t i = 0; i < count; ++i) {
    if (!(a[i] == b[i] || (std::isnan(a[i]) && std::isnan(b[i])))) return false;
  }
  return true;
}

// A cut C3D either reads the whole frames present, exactly as the whole file has them, with a "truncated"
// warning, or is refused with a DataError at a byte offset of that file. A damaged parameter section is
// refused at a byte offset, or read into consistent arrays.
TEST(C3dReader, DamagedFilesReadRightOrAreRefusedAtAByteOffset) {
  SYN_REQUIRE_SHARED("c3d/c3d_org/sample01/Eb015pi.c3d");
  const std::vector<uint8_t> original = ReadFileBytes(testing::SharedPath("c3d/c3d_org/sample01/Eb015pi.c3d"));
  const MarkerData full = ParseC3d(original.data(), original.size(), "full.c3d");
  int read_cut = 0, refused = 0;
  for (size_t cut = 0; cut < original.size(); cut += 97) {
    SCOPED_TRACE("cut at byte " + std::to_string(cut));
    try {
      const MarkerData data = ParseC3d(original.data(), cut, "cut.c3d");
      ++read_cut;
      EXPECT_EQ(data.labels, full.labels);
      ASSERT_LE(data.frame_count(), full.frame_count());
      ASSERT_EQ(data.points.size(), static_cast<size_t>(data.frame_count()) * data.labels.size() * 3);
      EXPECT_TRUE(SameValues(data.points.data(), full.points.data(), data.points.size()))
          << "the frames read differ from the whole file's";
      if (data.frame_count() < full.frame_count()) {
        bool warned = false;
        for (const std::string& warning : data.warnings) warned = warned || warning.find("truncated") != std::string::npos;
        EXPECT_TRUE(warned) << data.frame_count() << " of " << full.frame_count() << " frames without a warning";
      }
    } catch (const DataError& error) {
      ++refused;
      EXPECT_EQ(error.where().file, "cut.c3d");
      EXPECT_GE(error.where().byte_offset, 0) << error.what();
      EXPECT_NE(std::string(error.what()).find("byte offset"), std::string::npos) << error.what();
    }
  }
  EXPECT_GT(refused, 0);
  std::vector<uint8_t> damaged = original;
  for (size_t i = 512; i < 512 * 10; i += 13) {
    damaged[i] = static_cast<uint8_t>(damaged[i] * 31 + 7);
    try {
      const MarkerData data = ParseC3d(damaged.data(), damaged.size(), "damaged.c3d");
      EXPECT_EQ(data.points.size(), data.time_s.size() * data.labels.size() * 3) << "byte " << i;
    } catch (const DataError& error) {
      EXPECT_EQ(error.where().file, "damaged.c3d");
      EXPECT_GE(error.where().byte_offset, 0) << "byte " << i << ": " << error.what();
    }
  }
}

}  // namespace
}  // namespace syn

namespace syn {
namespace {

TEST(C3dReader, TheiaRotationsBecomeBodyPoses) {
  SYN_REQUIRE_SHARED("c3d/ezc3d/C3DRotationExample.c3d");
  const std::string path = testing::SharedPath("c3d/ezc3d/C3DRotationExample.c3d");
  const MarkerData data = ReadC3d(path);
  ASSERT_EQ(data.frame_count(), 340);
  ASSERT_EQ(data.bodies.size(), 21u);
  EXPECT_EQ(data.bodies[1], "pelvis_4X4");
  // Independent decoding of frame 100, segment 1: block 6, 17 little-endian floats per segment,
  // column-major 4×4 with the translation in elements 12–14.
  const std::vector<uint8_t> bytes = ReadFileBytes(path);
  float raw[17];
  std::memcpy(raw, &bytes[5 * 512 + (100 * 21 + 1) * 17 * 4], sizeof raw);
  const double* pose = &data.body_pose[(100 * 21 + 1) * 7];
  EXPECT_DOUBLE_EQ(pose[0], raw[12]);
  EXPECT_DOUBLE_EQ(pose[1], raw[13]);
  EXPECT_DOUBLE_EQ(pose[2], raw[14]);
  Eigen::Matrix3d rotation;
  for (int column = 0; column < 3; ++column) {
    for (int row = 0; row < 3; ++row) rotation(row, column) = raw[column * 4 + row];
  }
  const Eigen::Quaterniond expected(rotation);
  const Eigen::Quaterniond got(pose[3], pose[4], pose[5], pose[6]);
  EXPECT_LT(got.angularDistance(expected), 1e-6);
}

}  // namespace
}  // namespace syn
