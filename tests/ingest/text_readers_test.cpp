// TRC, Motive CSV and NPY readers on the shared real files, plus OpenSim's
// own reading of a C3D as a cross-check of the C3D reader.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "common/error.h"
#include "common/file_bytes.h"
#include "stages/ingest/bvh_reader.h"
#include "stages/ingest/c3d_reader.h"
#include "stages/ingest/motive_csv_reader.h"
#include "stages/ingest/npy_reader.h"
#include "stages/ingest/trc_reader.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

namespace fs = std::filesystem;

// Header facts read the simple way: the third line's whitespace-separated values.
struct TrcHeader {
  double rate = 0;
  int64_t frames = 0, markers = 0;
  std::string units;
};
TrcHeader ReadTrcHeader(const std::string& path) {
  std::ifstream in(path);
  std::string line;
  std::getline(in, line);
  std::getline(in, line);
  std::getline(in, line);
  std::istringstream values(line);
  TrcHeader header;
  double camera_rate = 0;
  values >> header.rate >> camera_rate >> header.frames >> header.markers >> header.units;
  return header;
}

TEST(TrcReader, EverySharedTrcMatchesItsHeader) {
  SYN_REQUIRE_SHARED("trc");
  int files = 0;
  for (const auto& entry : fs::recursive_directory_iterator(testing::SharedPath("trc"))) {
    if (entry.path().extension() != ".trc") continue;
    const std::string path = entry.path().string();
    SCOPED_TRACE(path);
    if (entry.path().filename() == "Truncated.trc") {
      try {
        (void)ReadTrc(path);
        ADD_FAILURE() << "a truncated header was accepted";
      } catch (const DataError& error) {
        EXPECT_GT(error.where().line, 0);
      }
      continue;
    }
    ++files;
    const TrcHeader header = ReadTrcHeader(path);
    const MarkerData data = ReadTrc(path);
    EXPECT_NEAR(data.rate_hz, header.rate, 1e-9);
    EXPECT_EQ(data.frame_count(), header.frames);
    EXPECT_EQ(data.marker_count(), header.markers);
    EXPECT_DOUBLE_EQ(data.length_unit_to_m, header.units == "mm" ? 0.001 : 1.0);
  }
  EXPECT_GE(files, 12);
}

TEST(TrcReader, BlankFieldsAndNanSpellingsAreMissing) {
  SYN_REQUIRE_SHARED("trc/opensim_format_edge_cases/exampleFormat.trc");
  const MarkerData data = ReadTrc(testing::SharedPath("trc/opensim_format_edge_cases/exampleFormat.trc"));
  ASSERT_EQ(data.labels, (std::vector<std::string>{"marker1", "marker2", "marker3"}));
  ASSERT_EQ(data.frame_count(), 5);
  EXPECT_TRUE(std::isnan(data.points[0]));       // frame 1, marker1: blank fields
  EXPECT_DOUBLE_EQ(data.points[3], -0.152);      // frame 1, marker2 x
  EXPECT_TRUE(std::isnan(data.points[2 * 9 + 3]));  // frame 3, marker2: Nan nan NAN
  EXPECT_DOUBLE_EQ(data.points[1 * 9 + 0], -0.273);
  EXPECT_DOUBLE_EQ(data.time_s[0], 0.01);
}

TEST(TrcReader, LabelsKeepInnerSpacesAndLoseOuterOnes) {
  SYN_REQUIRE_SHARED("trc/btk/Knee.trc");
  const MarkerData data = ReadTrc(testing::SharedPath("trc/btk/Knee.trc"));
  EXPECT_EQ(data.labels[0], "genou1_ NewMarker");
  EXPECT_EQ(data.labels[3], "genou1_NewMarker3");
}

TEST(TrcReader, NoMarkersAndCrlf) {
  const MarkerData with_axis_row = ParseTrc(
      "PathFileType\t4\t(X/Y/Z)\tz.trc\nDataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\n100\t100\t3\t0\tmm\n"
      "Frame#\tTime\t\n\t\t\n\n1\t0.00\n2\t0.01\n3\t0.02\n",
      "z.trc");
  EXPECT_EQ(with_axis_row.frame_count(), 3);
  EXPECT_EQ(with_axis_row.marker_count(), 0);
  const MarkerData crlf = ParseTrc(
      "PathFileType\t4\t(X/Y/Z)\tz.trc\r\nDataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\r\n100\t100\t2\t1\tm\r\n"
      "Frame#\tTime\tA\t\t\r\n\t\tX1\tY1\tZ1\r\n1\t0.00\t1\t2\t3\r\n2\t0.01\t4\t5\t6\r\n",
      "crlf.trc");
  ASSERT_EQ(crlf.frame_count(), 2);
  EXPECT_DOUBLE_EQ(crlf.points[5], 6.0);
  EXPECT_DOUBLE_EQ(crlf.length_unit_to_m, 1.0);
}

// A frame number no integer holds is a located error (found by fuzzing: the conversion was undefined).
TEST(TrcReader, HugeFrameNumberIsAnError) {
  try {
    (void)ParseTrc("PathFileType\t4\t(X/Y/Z)\tz.trc\nDataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\n"
                   "100\t100\t1\t0\tmm\nFrame#\tTime\t\n\t\t\n\n2e68\t0.00\n",
                   "z.trc");
    FAIL() << "expected an error";
  } catch (const DataError& error) {
    EXPECT_NE(std::string(error.what()).find("z.trc:7"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("out of range"), std::string::npos) << error.what();
  }
}

TEST(TrcReader, EFormatAndFractionalRate) {
  SYN_REQUIRE_SHARED("trc/opensim_format_edge_cases/dataWithEformat.trc");
  const MarkerData data = ReadTrc(testing::SharedPath("trc/opensim_format_edge_cases/dataWithEformat.trc"));
  EXPECT_DOUBLE_EQ(data.rate_hz, 119.88012);
  EXPECT_DOUBLE_EQ(data.length_unit_to_m, 1.0);
}

// OpenSim's C3DFileAdapter reading of walking2.c3d (every 10th frame, mm) against ours.
TEST(C3dCrossCheck, OpenSimReadingOfWalking2IsMatched) {
  SYN_REQUIRE_SHARED("c3d/opensim_reference/std_walking2_markers.trc");
  const MarkerData opensim = ReadTrc(testing::SharedPath("c3d/opensim_reference/std_walking2_markers.trc"));
  const MarkerData ours = ReadC3d(testing::SharedPath("c3d/opensim_reference/walking2.c3d"));
  ASSERT_EQ(opensim.length_unit_to_m, ours.length_unit_to_m);
  int64_t compared = 0;
  double worst_m = 0;
  for (size_t m = 0; m < opensim.labels.size(); ++m) {
    const auto found = std::find(ours.labels.begin(), ours.labels.end(), opensim.labels[m]);
    ASSERT_NE(found, ours.labels.end()) << opensim.labels[m];
    const size_t our_marker = static_cast<size_t>(found - ours.labels.begin());
    for (int64_t t = 0; t < opensim.frame_count(); ++t) {
      const int64_t frame = std::llround(opensim.time_s[static_cast<size_t>(t)] * ours.rate_hz);
      ASSERT_LT(frame, ours.frame_count());
      const double* theirs = &opensim.points[(static_cast<size_t>(t) * opensim.labels.size() + m) * 3];
      const double* mine = &ours.points[(static_cast<size_t>(frame) * ours.labels.size() + our_marker) * 3];
      ASSERT_EQ(std::isnan(theirs[0]), std::isnan(mine[0])) << opensim.labels[m] << " t=" << opensim.time_s[t];
      if (std::isnan(theirs[0])) continue;
      for (int axis = 0; axis < 3; ++axis) {
        // The reference holds 5 significant digits ("-2552.2", "300.46"): it is exact to half a unit in its last one.
        const double printed_step = std::pow(10.0, std::floor(std::log10(std::abs(theirs[axis]) + 1e-300)) - 4);
        const double difference = std::abs(theirs[axis] - mine[axis]);
        EXPECT_LE(difference, 0.5 * printed_step + 1e-6 * std::abs(theirs[axis])) << opensim.labels[m] << " t=" << opensim.time_s[t];
        worst_m = std::max(worst_m, difference * ours.length_unit_to_m);
      }
      ++compared;
    }
  }
  EXPECT_GT(compared, 1000);
  // Everywhere within the reference's own printing precision; in absolute terms within 0.05 mm.
  EXPECT_LT(worst_m, 5.01e-5);
  std::cout << "walking2: " << compared << " samples, worst difference " << worst_m * 1e3 << " mm\n";
}

TEST(MotiveCsvReader, MarkersExportReadsAsTheRawTextSays) {
  SYN_REQUIRE_SHARED("motive_csv/test_markers_enabled.csv");
  const std::string path = testing::SharedPath("motive_csv/test_markers_enabled.csv");
  const MarkerData data = ReadMotiveCsv(path);
  EXPECT_EQ(data.frame_count(), 1353);
  EXPECT_DOUBLE_EQ(data.rate_hz, 360.0);
  EXPECT_DOUBLE_EQ(data.length_unit_to_m, 0.001);
  EXPECT_EQ(data.labels[0], "Unlabeled 1036");
  // First data row, read here with plain string splitting.
  std::ifstream in(path);
  std::string line;
  for (int i = 0; i < 8; ++i) std::getline(in, line);
  std::vector<std::string> cells;
  std::stringstream row(line);
  for (std::string cell; std::getline(row, cell, ',');) cells.push_back(cell);
  EXPECT_DOUBLE_EQ(data.points[0], std::stod(cells[2]));
  EXPECT_DOUBLE_EQ(data.points[2], std::stod(cells[4]));
  EXPECT_DOUBLE_EQ(data.time_s[0], std::stod(cells[1]));
}

TEST(MotiveCsvReader, ExportWithoutDataColumnsSaysSo) {
  SYN_REQUIRE_SHARED("motive_csv/test_default.csv");
  try {
    (void)ReadMotiveCsv(testing::SharedPath("motive_csv/test_default.csv"));
    FAIL();
  } catch (const DataError& error) {
    EXPECT_NE(std::string(error.what()).find("no data columns"), std::string::npos) << error.what();
  }
}

TEST(MotiveCsvReader, RigidBodiesInQuaternionAndEulerAndBones) {
  const std::string quaternion_csv =
      "Format Version,1.23,Take Name,synthetic,Export Frame Rate,100.000000,Rotation Type,Quaternion,Length Units,Meters,Coordinate Space,Global\n"
      "\n"
      ",Type,Rigid Body,Rigid Body,Rigid Body,Rigid Body,Rigid Body,Rigid Body,Rigid Body,Bone,Bone,Bone,Bone,Bone,Bone,Bone,Marker,Marker,Marker\n"
      ",Name,Wand,Wand,Wand,Wand,Wand,Wand,Wand,Skel:Hip,Skel:Hip,Skel:Hip,Skel:Hip,Skel:Hip,Skel:Hip,Skel:Hip,M1,M1,M1\n"
      ",ID,1,1,1,1,1,1,1,2,2,2,2,2,2,2,3,3,3\n"
      ",,Rotation,Rotation,Rotation,Rotation,Position,Position,Position,Rotation,Rotation,Rotation,Rotation,Position,Position,Position,Position,Position,Position\n"
      "Frame,Time (Seconds),X,Y,Z,W,X,Y,Z,X,Y,Z,W,X,Y,Z,X,Y,Z\n"
      "0,0.000000,0,0,0.7071068,0.7071068,1,2,3,0,0,0,1,0.1,0.9,0.2,0.5,0.6,0.7\n"
      "1,0.010000,,,,,,,,0,0,0,1,0.1,0.9,0.2,,,\n";
  const MarkerData data = ParseMotiveCsv(quaternion_csv, "synthetic.csv");
  ASSERT_EQ(data.bodies, (std::vector<std::string>{"Wand", "Skel:Hip"}));
  ASSERT_EQ(data.labels, (std::vector<std::string>{"M1"}));
  // Wand: 90° about Y-up's Z: quaternion (w, x, y, z) = (cos 45°, 0, 0, sin 45°).
  EXPECT_NEAR(data.body_pose[3], std::sqrt(0.5), 1e-7);
  EXPECT_NEAR(data.body_pose[6], std::sqrt(0.5), 1e-7);
  EXPECT_DOUBLE_EQ(data.body_pose[0], 1.0);
  EXPECT_TRUE(std::isnan(data.body_pose[14]));  // frame 1, Wand: empty cells
  EXPECT_TRUE(std::isnan(data.points[3]));      // frame 1, M1
  EXPECT_DOUBLE_EQ(data.body_pose[14 + 7 + 1], 0.9);

  // Euler, order XYZ, degrees: R = Rx(90)·Ry(0)·Rz(90); check against Eigen here.
  const std::string euler_csv =
      "Format Version,1.23,Export Frame Rate,100,Rotation Type,XYZ,Length Units,Millimeters\n"
      ",Type,Rigid Body,Rigid Body,Rigid Body,Rigid Body,Rigid Body,Rigid Body\n"
      ",Name,Body,Body,Body,Body,Body,Body\n"
      ",,Rotation,Rotation,Rotation,Position,Position,Position\n"
      "Frame,Time (Seconds),X,Y,Z,X,Y,Z\n"
      "0,0,90,0,90,10,20,30\n";
  const MarkerData euler = ParseMotiveCsv(euler_csv, "euler.csv");
  const Eigen::Quaterniond expected(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()) *
                                    Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ()));
  const Eigen::Quaterniond got(euler.body_pose[3], euler.body_pose[4], euler.body_pose[5], euler.body_pose[6]);
  EXPECT_LT(got.angularDistance(expected), 1e-9);
  EXPECT_DOUBLE_EQ(euler.length_unit_to_m, 0.001);
}

TEST(NpyReader, HumanMl3dJointsMatchTheRawBytes) {
  SYN_REQUIRE_SHARED("humanml3d/new_joints_012314.npy");
  const std::string path = testing::SharedPath("humanml3d/new_joints_012314.npy");
  const MarkerData data = ReadHumanMl3dJoints(path);
  EXPECT_EQ(data.frame_count(), 170);
  EXPECT_EQ(data.bodies.size(), 22u);
  EXPECT_DOUBLE_EQ(data.rate_hz, 20.0);
  // Independent decoding: header length at bytes 8–9 (v1), then little-endian float32.
  const std::vector<uint8_t> bytes = ReadFileBytes(path);
  const size_t data_start = 10 + (bytes[8] | (bytes[9] << 8));
  for (size_t index : {size_t{0}, size_t{1}, size_t{100}, size_t{170 * 66 - 1}}) {
    float value;
    std::memcpy(&value, &bytes[data_start + 4 * index], 4);
    const size_t frame = index / 66, joint = (index % 66) / 3, axis = index % 3;
    EXPECT_DOUBLE_EQ(data.body_pose[(frame * 22 + joint) * 7 + axis], static_cast<double>(value)) << index;
  }
  EXPECT_TRUE(std::isnan(data.body_pose[3]));  // joints carry no orientation
}

TEST(NpyReader, RefusesWhatIsNotJointPositions) {
  SYN_REQUIRE_SHARED("humanml3d/mdm_results.npy");
  const auto message_of = [](const std::string& relative) {
    try {
      (void)ReadHumanMl3dJoints(testing::SharedPath(relative));
    } catch (const DataError& error) {
      return std::string(error.what());
    }
    return std::string();
  };
  EXPECT_NE(message_of("humanml3d/mdm_results.npy").find("pickled dict"), std::string::npos);
  EXPECT_NE(message_of("humanml3d/new_joint_vecs_012314.npy").find("feature-vector"), std::string::npos);
  for (int sample = 0; sample < 3; ++sample) {
    const MarkerData data =
        ReadHumanMl3dJoints(testing::SharedPath("humanml3d/derived/mdm_sample" + std::to_string(sample) + "_joints_T22x3.npy"));
    EXPECT_EQ(data.frame_count(), 60);
  }
  // float64 arrays parse too.
  const std::vector<uint8_t> bytes = ReadFileBytes(testing::SharedPath("humanml3d/momask_example_000612_vecs.npy"));
  const NpyArray array = ParseNpy(bytes.data(), bytes.size(), "momask.npy");
  EXPECT_EQ(array.dtype, "<f8");
  ASSERT_EQ(array.shape.size(), 2u);
  EXPECT_EQ(array.shape[1], 263);
}

// Inputs the fuzzers found; each must end in a DataError (under the sanitizers: without reading outside
// the input on the way).
TEST(FuzzRegressions, EachEndsInADataError) {
  const std::string folder = testing::SourcePath("tests/ingest/regressions");
  int count = 0;
  for (const auto& entry : fs::directory_iterator(folder)) {
    const std::vector<uint8_t> bytes = ReadFileBytes(entry.path().string());
    SCOPED_TRACE(entry.path().string());
    ++count;
    if (entry.path().extension() == ".npy") {
      EXPECT_THROW((void)HumanMl3dJointsToMarkerData(ParseNpy(bytes.data(), bytes.size(), "r.npy"), "r.npy"), DataError);
    }
    if (entry.path().extension() == ".c3d") {
      // c3d_parameter_dimensions_overflow.c3d: a parameter whose dimensions multiply past size_t; the
      // wrapped count passed the bounds check and its values were read past the end of the file.
      EXPECT_THROW((void)ParseC3d(bytes.data(), bytes.size(), "r.c3d"), DataError);
    }
    if (entry.path().extension() == ".bvh") {
      // bvh_one_frame_dropped.bvh: a take of one frame read with its first frame dropped; the lead-in check
      // after the drop read the frame after it, past the end of the values.
      BvhOptions drop;
      drop.drop_first_frame = true;
      EXPECT_THROW((void)ParseBvh(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), "r.bvh", drop),
                   DataError);
    }
    if (entry.path().extension() == ".trc") {
      EXPECT_THROW((void)ParseTrc(std::string_view(reinterpret_cast<const char*>(bytes.data()), bytes.size()), "r.trc"),
                   DataError);
    }
  }
  EXPECT_GE(count, 1);
}

// Every prefix of a small TRC either reads the frames whose lines are whole, as the whole file has them, or
// is refused with a DataError at a line of that file; a short NPY header is refused at a byte offset.
TEST(TextReaders, DamagedInputsReadRightOrAreRefusedWithALocation) {
  const std::string trc = "PathFileType\t4\t(X/Y/Z)\tx.trc\nDataRate\tCameraRate\tNumFrames\tNumMarkers\tUnits\n100\t100\t2\t1\tmm\n"
                          "Frame#\tTime\tA\t\t\n\t\tX1\tY1\tZ1\n1\t0\t1\t2\t3\n2\t0.01\t4\t5\t6\n";
  const MarkerData full = ParseTrc(trc, "full.trc");
  ASSERT_EQ(full.frame_count(), 2);
  int read = 0, refused = 0;
  for (size_t cut = 0; cut < trc.size(); ++cut) {
    SCOPED_TRACE("cut at byte " + std::to_string(cut));
    try {
      const MarkerData data = ParseTrc(trc.substr(0, cut), "cut.trc");
      ++read;
      // What differs from the whole file is said: labels cut off are named Marker<N> and rows cut off are
      // counted against NumFrames, each with a warning.
      const auto warned = [&](const std::string& about) {
        for (const std::string& warning : data.warnings) {
          if (warning.find(about) != std::string::npos) return true;
        }
        return false;
      };
      if (data.labels != full.labels) {
        EXPECT_TRUE(warned("NumMarkers says")) << data.labels[0];
      }
      if (data.frame_count() != full.frame_count()) {
        EXPECT_TRUE(warned("NumFrames says")) << data.frame_count();
      }
      ASSERT_LE(data.frame_count(), full.frame_count());
      ASSERT_EQ(data.points.size(), static_cast<size_t>(data.frame_count()) * 3);
      for (int64_t t = 0; t < data.frame_count(); ++t) EXPECT_EQ(data.time_s[t], full.time_s[t]) << "frame " << t;
      for (size_t k = 0; k < data.points.size(); ++k) {
        // A value is the whole file's, or missing: a cut number ("4" of "45") must never pass as a value.
        EXPECT_TRUE(data.points[k] == full.points[k] || std::isnan(data.points[k])) << k << ": " << data.points[k];
      }
    } catch (const DataError& error) {
      ++refused;
      EXPECT_EQ(error.where().file, "cut.trc");
      EXPECT_GT(error.where().line, 0) << error.what();
    }
  }
  EXPECT_GE(read, 1);
  EXPECT_GT(refused, 0);
  std::vector<uint8_t> npy = {0x93, 'N', 'U', 'M', 'P', 'Y', 1, 0, 200, 0};
  try {
    (void)ParseNpy(npy.data(), npy.size(), "short.npy");
    ADD_FAILURE() << "a 10-byte NPY was accepted";
  } catch (const DataError& error) {
    EXPECT_EQ(error.where().file, "short.npy");
    EXPECT_GE(error.where().byte_offset, 0);
    EXPECT_NE(std::string(error.what()).find("byte offset"), std::string::npos);
  }
}

}  // namespace
}  // namespace syn
