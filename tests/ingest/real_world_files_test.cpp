// Files from other labs that used to fail: TRC headers padded with runs of tabs, text in Latin-1 or
// with stray bytes, and captures whose vertical axis is not the format's convention. Fixtures in
// tests/ingest/fixtures/ (written by make_fixtures.py from OpenSim's gait2354 walking trial).
#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>

#include "common/error.h"
#include "common/file_bytes.h"
#include "common/markers_file.h"
#include "common/text_encoding.h"
#include "stages/ingest/c3d_reader.h"
#include "stages/ingest/ingest.h"
#include "stages/ingest/trc_reader.h"
#include "stages/ingest/up_axis.h"
#include "tests/support/run_command.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

namespace fs = std::filesystem;

std::string Fixture(const std::string& name) { return testing::SourcePath("tests/ingest/fixtures/" + name); }

fs::path TempDir() {
  const fs::path dir = fs::temp_directory_path() / ("syn_real_world_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  return dir;
}

// ---- text encoding: the one rule -------------------------------------------------------------------

TEST(TextEncoding, ValidUtf8StaysLatin1IsDecodedTheRestIsEscaped) {
  EXPECT_EQ(ToUtf8("LASI"), "LASI");
  EXPECT_EQ(ToUtf8("\xC3\xA9paule"), "\xC3\xA9paule");          // already UTF-8: kept
  EXPECT_EQ(ToUtf8("\xC9paule"), "\xC3\x89paule");              // Latin-1 É -> U+00C9
  EXPECT_EQ(ToUtf8("caf\xE9"), "caf\xC3\xA9");                  // a lone lead byte at the end
  EXPECT_EQ(ToUtf8("R\x81Knee"), "R\\x81Knee");                 // C1 control: escaped
  EXPECT_EQ(ToUtf8("\xED\xA0\x80"), "\xC3\xAD\xC2\xA0\\x80");  // a UTF-16 surrogate is not UTF-8: byte by byte
  EXPECT_EQ(ToUtf8("\xC0\xAF"), "\xC3\x80\xC2\xAF");            // overlong '/' is not UTF-8
  EXPECT_TRUE(IsValidUtf8(ToUtf8(std::string("\xFF\xFE\x80\x00x", 5))));
  EXPECT_EQ(Printable("a\x01" "b\x7F\tc"), "a\\x01b\\x7F\tc");
  nlohmann::json value = {{"k\xE9y", {"v\xE9", 1}}};
  MakeJsonUtf8(value);
  EXPECT_EQ(value.dump(), "{\"k\xC3\xA9y\":[\"v\xC3\xA9\",1]}");
}

TEST(TextEncoding, ErrorMessagesEscapeControlBytes) {
  const DataError error(Location::AtLine("f.trc", 3), "Units 'm\x01\x1B[2J': expected mm, cm or m");
  EXPECT_EQ(std::string(error.what()), "f.trc:3: Units 'm\\x01\\x1B[2J': expected mm, cm or m");
}

// ---- case 4: tab-padded TRC headers -------------------------------------------------------------------

TEST(RealWorldFiles, TabPaddedTrcHeaderReadsLikeThePlainOne) {
  const MarkerData plain = ReadTrc(Fixture("walk_y_up.trc"));
  const MarkerData padded = ReadTrc(Fixture("walk_tab_padded.trc"));
  EXPECT_EQ(padded.rate_hz, 6.0);
  EXPECT_EQ(padded.labels.size(), 41u);
  EXPECT_EQ(padded.frame_count(), 16);
  EXPECT_EQ(padded.length_unit_to_m, 0.001);
  EXPECT_EQ(padded.labels, plain.labels);
  ASSERT_EQ(padded.points.size(), plain.points.size());
  for (size_t i = 0; i < plain.points.size(); ++i) ASSERT_EQ(padded.points[i], plain.points[i]) << i;
  EXPECT_TRUE(padded.warnings.empty()) << padded.warnings.front();
  // The numbers themselves, against the file's text: frame 1, R.ASIS.
  EXPECT_DOUBLE_EQ(padded.points[0], 617.24762);
  EXPECT_DOUBLE_EQ(padded.points[1], 1055.27502);
  EXPECT_DOUBLE_EQ(padded.points[2], 170.78198);
}

TEST(RealWorldFiles, TabPaddingDoesNotHideAnEmptyValue) {
  // Positional columns still win when the row has as many fields as keys: an empty NumFrames stays empty.
  const std::string text =
      "PathFileType\t4\t(X/Y/Z)\tx.trc\nDataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\n"
      "100\t100\t\t1\tmm\nFrame#\tTime\tA\t\t\n\t\tX1\tY1\tZ1\n\n1\t0\t1\t2\t3\n";
  try {
    (void)ParseTrc(text, "x.trc");
    FAIL() << "an empty NumFrames must be refused";
  } catch (const DataError& error) {
    EXPECT_NE(std::string(error.what()).find("NumFrames"), std::string::npos) << error.what();
  }
}

// ---- case 3: text that is not UTF-8 -----------------------------------------------------------------

TEST(RealWorldFiles, Latin1LabelsBecomeUtf8InMemoryAndInTheMarkersFile) {
  IngestSummary summary;
  const MarkerData data = IngestCapture(Fixture("latin1_label.trc"), {}, &summary);
  ASSERT_EQ(data.labels.size(), 3u);
  EXPECT_EQ(data.labels[0], "\xC3\x89paule");
  EXPECT_EQ(data.labels[1], "R\\x81Knee");
  EXPECT_EQ(data.labels[2], "Head");
  EXPECT_DOUBLE_EQ(data.points[0 * 3 + 2], 1.4);  // Y up (1400 mm) became Z
  // Through the tool: no internal error, and the HDF5 file holds the same UTF-8 labels.
  const fs::path dir = TempDir();
  const std::string output = (dir / "latin1.markers.h5").string();
  const testing::CommandResult run =
      testing::RunCommand(testing::BinPath("syn-ingest") + " '" + Fixture("latin1_label.trc") + "' -o '" + output + "'");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(run.output.find("internal error"), std::string::npos) << run.output;
  EXPECT_TRUE(IsValidUtf8(run.output)) << run.output;
  const MarkerData stored = ReadMarkersFile(output);
  EXPECT_EQ(stored.labels, data.labels);
  fs::remove_all(dir);
}

TEST(RealWorldFiles, C3dWithLatin1AndGarbageTextIngestsAndStoresUtf8) {
  SYN_REQUIRE_SHARED("c3d/c3d_org/sample01/Eb015pi.c3d");
  std::vector<uint8_t> bytes = ReadFileBytes(testing::SharedPath("c3d/c3d_org/sample01/Eb015pi.c3d"));
  const std::vector<C3dParameter> parameters = ParseC3dParameters(bytes.data(), bytes.size(), "x");
  const MarkerData original = ParseC3d(bytes.data(), bytes.size(), "x");
  // Overwrite the first label's first two characters (in the POINT:LABELS data) with Latin-1 'é' and a C1 byte,
  // and a manufacturer-style byte 0x1B in the second label.
  const std::string first = original.labels[0], second = original.labels[1];
  const std::string needle = first + std::string(4 - std::min<size_t>(first.size(), 4), ' ');
  const auto at = std::search(bytes.begin() + 512, bytes.end(), first.begin(), first.end());
  ASSERT_NE(at, bytes.end());
  at[0] = 0xE9;
  at[1] = 0x81;
  const auto at2 = std::search(bytes.begin() + 512, bytes.end(), second.begin(), second.end());
  ASSERT_NE(at2, bytes.end());
  at2[0] = 0x1B;
  const fs::path dir = TempDir();
  const std::string damaged = (dir / "latin1.c3d").string();
  {
    std::ofstream out(damaged, std::ios::binary);
    out.write(reinterpret_cast<const char*>(bytes.data()), static_cast<std::streamsize>(bytes.size()));
  }
  IngestSummary summary;
  const MarkerData data = IngestCapture(damaged, {}, &summary);
  EXPECT_EQ(data.labels[0], "\xC3\xA9\\x81" + first.substr(2));
  EXPECT_EQ(data.labels[1], "\x1B" + second.substr(1));  // valid UTF-8 control characters are stored as they are
  const std::string output = (dir / "latin1.markers.h5").string();
  const testing::CommandResult run = testing::RunCommand(testing::BinPath("syn-ingest") + " '" + damaged + "' -o '" + output + "'");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_EQ(run.output.find("internal error"), std::string::npos) << run.output;
  EXPECT_EQ(ReadMarkersFile(output).labels, data.labels);
  fs::remove_all(dir);
  (void)parameters;
  (void)needle;
}

TEST(RealWorldFiles, GarbageInAHeaderFieldGivesALocatedPrintableError) {
  const std::string text =
      "PathFileType\t4\t(X/Y/Z)\tx.trc\nDataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\n"
      "100\t100\t1\t1\tm\x01\x9B\xFF\nFrame#\tTime\tA\t\t\n\t\tX1\tY1\tZ1\n\n1\t0\t1\t2\t3\n";
  try {
    (void)ParseTrc(text, "x.trc");
    FAIL() << "a unit of garbage must be refused";
  } catch (const DataError& error) {
    const std::string message = error.what();
    EXPECT_EQ(message, "x.trc:3: Units 'm\\x01\\x9B\xC3\xBF': expected mm, cm or m");
    EXPECT_TRUE(IsValidUtf8(message));
  }
}

// ---- case 5: the vertical axis ----------------------------------------------------------------------

TEST(RealWorldFiles, ZUpAndYUpCopiesOfOneTrialIngestIdentically) {
  IngestSummary y_summary, z_summary;
  const MarkerData y_up = IngestCapture(Fixture("walk_y_up.trc"), {}, &y_summary);
  const MarkerData z_up = IngestCapture(Fixture("walk_z_up.trc"), {}, &z_summary);
  EXPECT_EQ(y_summary.up_axis, 'y');
  EXPECT_EQ(z_summary.up_axis, 'z');
  EXPECT_EQ(z_summary.up_axis_reason.rfind("data: ", 0), 0u) << z_summary.up_axis_reason;
  EXPECT_NE(z_summary.BriefReport().find("up axis Z (data: extent z"), std::string::npos) << z_summary.BriefReport();
  // The Z-up file disagrees with the TRC convention (Y): a warning says so.
  bool warned = false;
  for (const std::string& warning : z_up.warnings) warned = warned || warning.find("the data says Z is up, not the format's Y") != std::string::npos;
  EXPECT_TRUE(warned);
  for (const std::string& warning : y_up.warnings) EXPECT_EQ(warning.find("the data says"), std::string::npos) << warning;
  ASSERT_EQ(z_up.points.size(), y_up.points.size());
  double worst = 0;
  for (size_t i = 0; i < y_up.points.size(); ++i) worst = std::max(worst, std::abs(z_up.points[i] - y_up.points[i]));
  EXPECT_EQ(worst, 0.0);
  // Upright: the head markers are the highest, about 1.5-1.8 m above the lowest (foot) marker.
  double lowest = INFINITY, highest = -INFINITY;
  for (size_t m = 0; m < y_up.labels.size(); ++m) {
    lowest = std::min(lowest, y_up.points[m * 3 + 2]);
    highest = std::max(highest, y_up.points[m * 3 + 2]);
  }
  EXPECT_GT(highest - lowest, 1.4);
  EXPECT_LT(highest - lowest, 2.0);
}

// BTK wrote Gait.trc from Gait.c3d without turning it Y up: read by the data, both land in the same place.
TEST(RealWorldFiles, GaitTrcAndItsC3dIngestToTheSamePlace) {
  SYN_REQUIRE_SHARED("trc/btk/Gait.trc");
  SYN_REQUIRE_SHARED("c3d/btk_others/Gait.c3d");
  IngestSummary trc_summary, c3d_summary;
  const MarkerData trc = IngestCapture(testing::SharedPath("trc/btk/Gait.trc"), {}, &trc_summary);
  const MarkerData c3d = IngestCapture(testing::SharedPath("c3d/btk_others/Gait.c3d"), {}, &c3d_summary);
  EXPECT_EQ(trc_summary.up_axis, 'z');
  EXPECT_EQ(c3d_summary.up_axis, 'z');
  ASSERT_EQ(trc.frame_count(), c3d.frame_count());
  ASSERT_EQ(trc.labels[0], "R.Shoulder");
  ASSERT_EQ(c3d.labels[0], "RSHO");
  double worst = 0;
  for (int64_t t = 0; t < trc.frame_count(); ++t) {
    for (int a = 0; a < 3; ++a) {
      const double x = trc.points[static_cast<size_t>(t) * trc.labels.size() * 3 + a];
      const double y = c3d.points[static_cast<size_t>(t) * c3d.labels.size() * 3 + a];
      if (!std::isnan(x) && !std::isnan(y)) worst = std::max(worst, std::abs(x - y));
    }
  }
  EXPECT_LT(worst, 0.001);  // m: the TRC's text rounding
}

TEST(RealWorldFiles, UpAxisOverrideAndUndecidableData) {
  IngestOptions options;
  options.up_axis = "y";
  IngestSummary summary;
  (void)IngestCapture(Fixture("walk_z_up.trc"), options, &summary);
  EXPECT_EQ(summary.up_axis, 'y');
  EXPECT_EQ(summary.up_axis_reason, "--up-axis y");
  // The three Latin-1 markers span 1.2 m along Y and 5 cm across: tall along Y, decided from the data.
  (void)IngestCapture(Fixture("latin1_label.trc"), {}, &summary);
  EXPECT_EQ(summary.up_axis, 'y');
  EXPECT_EQ(summary.up_axis_reason.rfind("data: extent y 1.20 m", 0), 0u) << summary.up_axis_reason;
}

TEST(UpAxis, DataThatCannotTellFallsBackToTheConvention) {
  // The corners of a 1 m cube, standing still: no axis is taller, no floor is seen travelling.
  MarkerData cube;
  cube.rate_hz = 10;
  for (int t = 0; t < 5; ++t) {
    cube.time_s.push_back(t * 0.1);
    for (int corner = 0; corner < 8; ++corner) {
      cube.points.insert(cube.points.end(), {double(corner & 1), double((corner >> 1) & 1), double((corner >> 2) & 1)});
    }
  }
  cube.labels.assign(8, "c");
  UpAxisDecision decision = DecideUpAxis(cube, 'y', 1.0);
  EXPECT_EQ(decision.axis, 'y');
  EXPECT_FALSE(decision.from_data);
  EXPECT_EQ(decision.reason.rfind("the format's convention (y up): the data cannot tell", 0), 0u) << decision.reason;
  decision = DecideUpAxis(cube, '?', 1.0);
  EXPECT_EQ(decision.axis, 'z');
  // Lying along X and rolling across the floor (z = 0.1 m) diagonally: the cues disagree, so the convention stands.
  MarkerData lying;
  lying.rate_hz = 10;
  for (int t = 0; t < 20; ++t) {
    lying.time_s.push_back(t * 0.1);
    for (int m = 0; m < 10; ++m) lying.points.insert(lying.points.end(), {0.17 * m + 0.05 * t, 0.1 * t + 0.03 * (m % 2), 0.1 + 0.02 * (m % 3)});
  }
  lying.labels.assign(10, "m");
  decision = DecideUpAxis(lying, 'z', 1.0);
  EXPECT_EQ(decision.axis, 'z');
  EXPECT_FALSE(decision.from_data);
  EXPECT_NE(decision.reason.find("cues disagree"), std::string::npos) << decision.reason;
}

// Every real capture in ../shared gets its known vertical axis: the format's convention (CMU BVH and
// OpenSim TRC Y up, C3D by POINT:Y_SCREEN or Z) except where the file breaks it, which the data shows
// (foot markers at floor height, head markers at the top, read from each file with --up-axis z):
//   trc/btk/Gait.trc            BTK's TRC of btk_others/Gait.c3d, left in the C3D's Z-up frame: C7 at
//                               z = 1.41 m, R.Foot.Lateral at z = 0.02 m (checked against Gait.c3d below)
//   std_walking2_markers.trc    OpenSim's C3DFileAdapter output for walking2.c3d, also unrotated: RFHD at
//                               z = 1.73 m, LMT2 at z = 0.05 m
//   sample28/type1, dynamic     BTS files without POINT:Y_SCREEN, Y up: SACR at y = 0.96 m, LMET at 0.016 m
//   sample13/Dance.c3d          PhoeniX, X up: a 1.7 m dancer along x, the lowest marker at x = 0.06 m
// ezc3d/Optotrak.c3d (29 frames of unnamed markers, 1.5 m along x) is printed, not asserted: its axis is
// not known from the file. The rule must decide most files from the data, not by falling back.
TEST(RealWorldFiles, AutoUpAxisGivesTheKnownAxisOfEverySharedCapture) {
  SYN_REQUIRE_SHARED("c3d");
  const std::map<std::string, char> breaks_convention = {{"trc/btk/Gait.trc", 'z'},
                                                          {"c3d/opensim_reference/std_walking2_markers.trc", 'z'},
                                                          {"c3d/c3d_org/sample28/type1.C3D", 'y'},
                                                          {"c3d/c3d_org/sample28/dynamic.C3D", 'y'},
                                                          {"c3d/c3d_org/sample13/Dance.c3d", 'x'}};
  const std::set<std::string> unknown = {"c3d/ezc3d/Optotrak.c3d"};
  int files = 0, from_data = 0, overridden = 0;
  for (const char* folder : {"cmu_bvh", "trc", "c3d"}) {
    for (const auto& entry : fs::recursive_directory_iterator(testing::SharedPath(folder))) {
      std::string extension = entry.path().extension().string();
      for (char& c : extension) c = static_cast<char>(std::tolower(static_cast<unsigned char>(c)));
      if (extension != ".bvh" && extension != ".trc" && extension != ".c3d") continue;
      IngestSummary summary;
      MarkerData data;
      try {
        data = IngestCapture(entry.path().string(), {}, &summary);
      } catch (const DataError&) {
        continue;  // unreadable files are tested elsewhere
      }
      ++files;
      const std::string relative = entry.path().lexically_relative(testing::SharedPath("")).string();
      std::cout << relative << ": up " << summary.up_axis << " (" << summary.up_axis_reason << ")\n";
      from_data += summary.up_axis_reason.rfind("data: ", 0) == 0;
      if (unknown.count(relative)) continue;
      const auto known = breaks_convention.find(relative);
      if (known != breaks_convention.end()) {
        ++overridden;
        EXPECT_EQ(summary.up_axis, known->second) << relative << ": " << summary.up_axis_reason;
        continue;
      }
      for (const std::string& warning : data.warnings) {
        EXPECT_EQ(warning.find("the data says"), std::string::npos) << relative << ": " << warning;
      }
    }
  }
  EXPECT_EQ(overridden, 5);
  EXPECT_GE(files, 100);
  EXPECT_GE(from_data * 10, files * 6) << from_data << " of " << files << " decided from the data";
}

}  // namespace
}  // namespace syn
