// syn-export's robot-learning formats, re-read with numpy and checked against an independent forward
// kinematics from the URDF (tests/export/check_exports.py), on a real G1 motion (NVIDIA Kimodo jumping
// jacks, ../shared/datasets/robot_motion). Also the NPY/NPZ bytes themselves.
#include <gtest/gtest.h>
#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>

#include "common/error.h"
#include "common/file_bytes.h"
#include "common/intermediate_file.h"
#include "common/model.h"
#include "common/motion_file.h"
#include "stages/export/motion_export.h"
#include "stages/export/npz_writer.h"
#include "stages/export/robot_learning_export.h"
#include "tests/support/demo_motion.h"
#include "tests/support/run_command.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

namespace fs = std::filesystem;

// A python3 that has numpy (Debian's python3-numpy), or "" (tests skip, saying so).
std::string PythonWithNumpy() {
  for (const char* python : {"python3", "/usr/bin/python3"}) {
    if (testing::RunCommand(std::string(python) + " -c 'import numpy'").exit_code == 0) return python;
  }
  return "";
}

TEST(NpzWriter, NpyHeaderAndZipLayout) {
  const std::string npy = NpyBytes(NpyArray::Numbers("x", {2, 3}, {1, 2, 3, 4, 5, 6}));
  ASSERT_GE(npy.size(), 64u + 48u);
  EXPECT_EQ(npy.substr(0, 8), std::string("\x93NUMPY\x01\x00", 8));
  const size_t header_length = static_cast<uint8_t>(npy[8]) | (static_cast<uint8_t>(npy[9]) << 8);
  EXPECT_EQ((10 + header_length) % 64, 0u);
  EXPECT_EQ(npy.substr(10, 59), "{'descr': '<f8', 'fortran_order': False, 'shape': (2, 3), }");
  EXPECT_EQ(npy.size(), 10 + header_length + 6 * 8);
  double last;
  std::memcpy(&last, npy.data() + npy.size() - 8, 8);
  EXPECT_EQ(last, 6.0);
  EXPECT_EQ(Crc32("123456789"), 0xCBF43926u);  // the CRC-32 check value
  EXPECT_THROW((void)NpyBytes(NpyArray::Numbers("x", {2, 2}, {1, 2, 3})), std::invalid_argument);
  // Same arrays, same bytes.
  EXPECT_EQ(NpzBytes({NpyArray::Numbers("a", {1}, {1.5}), NpyArray::Text("n", {"x", "yz"})}),
            NpzBytes({NpyArray::Numbers("a", {1}, {1.5}), NpyArray::Text("n", {"x", "yz"})}));
}

TEST(NpzWriter, NumpyReadsItBack) {
  const std::string python = PythonWithNumpy();
  if (python.empty()) GTEST_SKIP() << "python3 with numpy absent (Debian package python3-numpy)";
  const fs::path path = fs::temp_directory_path() / ("syn_npz_" + std::to_string(::getpid()) + ".npz");
  WriteFileAtomically(path.string(), NpzBytes({NpyArray::Numbers("scalar", {}, {30.0}),
                                               NpyArray::Numbers("matrix", {2, 2}, {1, -2, 3.25, 1e-300}),
                                               NpyArray::Text("names", {"pelvis", "h\xC3\xA9", ""})}));
  const testing::CommandResult run = testing::RunCommand(
      python + " -c \"import numpy as np; d = np.load('" + path.string() +
      "', allow_pickle=False); assert d['scalar'].shape == () and d['scalar'] == 30.0; "
      "assert d['matrix'].tolist() == [[1, -2], [3.25, 1e-300]]; assert list(d['names']) == ['pelvis', 'h\\u00e9', '']; "
      "print(sorted(d.files))\"");
  EXPECT_EQ(run.exit_code, 0) << run.output;
  EXPECT_NE(run.output.find("['matrix', 'names', 'scalar']"), std::string::npos) << run.output;
  fs::remove(path);
}

TEST(RobotLearningExport, NumpyReadsEveryFormatAndItMatchesTheMotionAndTheUrdf) {
  SYN_REQUIRE_SHARED("robot_motion/g1_kimodo_jumpjack.csv");
  const std::string python = PythonWithNumpy();
  if (python.empty()) GTEST_SKIP() << "python3 with numpy absent (Debian package python3-numpy)";
  const std::string urdf = testing::SourcePath(testing::kG1Urdf);
  const std::string source = testing::SharedPath("robot_motion/g1_kimodo_jumpjack.csv");
  const Model model = Model::Load(urdf);
  MotionData motion = ReadRobotCsv(source, model, 30.0);
  // A robot CSV has poses only; the motion file also stores velocities, accelerations and torques.
  for (std::vector<double>* values : {&motion.u, &motion.udot, &motion.tau}) {
    values->assign(static_cast<size_t>(motion.frames() * motion.nu()), 0.0);
  }
  const fs::path dir = fs::temp_directory_path() / ("syn_export_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const std::string motion_path = (dir / "jumpjack.motion.h5").string();
  {
    Provenance provenance;
    provenance.schema = kMotionSchema;
    provenance.schema_version = kMotionSchemaVersion;
    provenance.producer = "robot_learning_export_test";
    IntermediateWriter writer(motion_path, provenance);
    WriteMotionData(writer, motion);
    writer.commit();
  }
  const auto export_as = [&](const std::string& format, const std::string& name) {
    const std::string output = (dir / name).string();
    const testing::CommandResult run = testing::RunCommand(testing::BinPath("syn-export") + " " + motion_path + " -o " +
                                                           output + " --format " + format + " --model " + urdf);
    EXPECT_EQ(run.exit_code, 0) << run.output;
    return output;
  };
  const std::string unitree = export_as("unitree-csv", "jumpjack_unitree.csv");
  const std::string gmr = export_as("gmr-npz", "jumpjack_gmr.npz");
  const std::string mjlab = export_as("mjlab-npz", "jumpjack_mjlab.npz");
  const testing::CommandResult check = testing::RunCommand(python + " " + testing::SourcePath("tests/export/check_exports.py") +
                                                           " " + urdf + " " + source + " 30 " + unitree + " " + gmr + " " + mjlab);
  EXPECT_EQ(check.exit_code, 0) << check.output;
  EXPECT_EQ(check.output.rfind("ok: ", 0), 0u) << check.output;
  std::cout << check.output;
  // Deterministic: a second export is byte-identical.
  const std::string again = (dir / "again.npz").string();
  ASSERT_EQ(testing::RunCommand(testing::BinPath("syn-export") + " " + motion_path + " -o " + again +
                                " --format mjlab-npz --model " + urdf).exit_code, 0);
  EXPECT_EQ(ReadFileBytes(again), ReadFileBytes(mjlab));
  fs::remove_all(dir);
}

TEST(RobotLearningExport, UnevenFramesAndWrongModelsAreRefused) {
  SYN_REQUIRE_SHARED("robot_motion/g1_kimodo_jumpjack.csv");
  const Model model = Model::Load(testing::SourcePath(testing::kG1Urdf));
  MotionData motion = ReadRobotCsv(testing::SharedPath("robot_motion/g1_kimodo_jumpjack.csv"), model, 30.0);
  motion.time_s[5] += 0.01;
  try {
    (void)MotionToMjlabNpz(motion, model);
    FAIL() << "uneven frames were accepted";
  } catch (const DataError& error) {
    EXPECT_NE(std::string(error.what()).find("frame 5: frames are not evenly spaced"), std::string::npos) << error.what();
  }
  motion.coordinate_names[7] = "elsewhere";
  EXPECT_THROW((void)MotionToUnitreeCsv(motion, model), DataError);
  EXPECT_THROW((void)MotionToGmrNpz(motion, model), DataError);
}

}  // namespace
}  // namespace syn
