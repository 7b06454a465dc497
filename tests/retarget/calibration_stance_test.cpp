// A robot map's [calibration_stance]: the capture's calibration frame (BVH frame 0, kept by syn-ingest
// --drop-first-frame) is the reference, wherever and facing wherever the subject stood for it.
#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <string>
#include <unistd.h>

#include "common/file_bytes.h"
#include "common/intermediate_file.h"
#include "common/markers_file.h"
#include "stages/ingest/ingest.h"
#include "stages/retarget/retarget.h"
#include "common/percentile.h"
#include "tests/support/demo_motion.h"
#include "tests/support/independent_fk.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

namespace fs = std::filesystem;

class CalibrationStance : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("syn_calibration_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    IngestOptions ingest;
    ingest.drop_first_frame = true;
    walk_ = IngestCapture(testing::SourcePath("datasets/demo/02_01.bvh"), ingest, nullptr);
    // G1's map with a calibration stance: the same straight stance as its reference stance.
    map_ = dir_ + "/g1_calibrated.toml";
    std::ofstream(map_) << ReadFileText(testing::SourcePath("manifests/robots/g1.toml")) << "\n[calibration_stance]\n";
  }
  void TearDown() override { fs::remove_all(dir_); }

  MotionData Retarget(const MarkerData& capture, const std::string& map, RetargetSummary* summary) {
    const std::string path = dir_ + "/walk.markers.h5";
    IntermediateWriter writer(path, {kMarkersSchema, kMarkersSchemaVersion, "test", {}, nlohmann::json::array()});
    WriteMarkerData(writer, capture);
    writer.commit();
    RetargetOptions options;
    options.model = testing::SourcePath(testing::kG1Urdf);
    options.robot_map = map;
    options.markerset = testing::SourcePath("manifests/markersets/cmu-bvh.toml");
    return RetargetFile(path, options, summary);
  }

  std::string dir_, map_;
  MarkerData walk_;
};

TEST_F(CalibrationStance, IsTheReferenceOnlyWhenBothMapAndCaptureHaveIt) {
  ASSERT_EQ(walk_.calibration_body_pose.size(), walk_.bodies.size() * 7);
  RetargetSummary calibrated, plain, missing;
  (void)Retarget(walk_, map_, &calibrated);
  EXPECT_EQ(calibrated.reference_frame, -1);
  (void)Retarget(walk_, testing::SourcePath("manifests/robots/g1.toml"), &plain);
  EXPECT_EQ(plain.reference_frame, 0);
  MarkerData without = walk_;
  without.calibration_body_pose.clear();
  (void)Retarget(without, map_, &missing);
  EXPECT_EQ(missing.reference_frame, 0);
  bool noted = false;
  for (const std::string& note : missing.notes) noted = noted || note.find("no calibration frame") != std::string::npos;
  EXPECT_TRUE(noted);
}

// Turning and moving the whole calibration frame about the vertical (the subject stood elsewhere, facing
// elsewhere, for the T-pose) changes nothing: it is brought to where the take starts, facing its way.
TEST_F(CalibrationStance, WhereTheSubjectStoodForItDoesNotMatter) {
  MarkerData turned = walk_;
  const Eigen::Quaterniond turn(Eigen::AngleAxisd(2.6, Eigen::Vector3d::UnitZ()));
  const Eigen::Vector3d move(1.5, -0.7, 0.0);
  for (size_t b = 0; b < turned.bodies.size(); ++b) {
    double* pose = &turned.calibration_body_pose[b * 7];
    const Eigen::Vector3d position = turn * Eigen::Vector3d(pose[0], pose[1], pose[2]) + move;
    const Eigen::Quaterniond orientation = turn * Eigen::Quaterniond(pose[3], pose[4], pose[5], pose[6]);
    pose[0] = position.x(), pose[1] = position.y(), pose[2] = position.z();
    pose[3] = orientation.w(), pose[4] = orientation.x(), pose[5] = orientation.y(), pose[6] = orientation.z();
  }
  RetargetSummary as_recorded, moved;
  const MotionData a = Retarget(walk_, map_, &as_recorded);
  const MotionData b = Retarget(turned, map_, &moved);
  ASSERT_EQ(a.q.size(), b.q.size());
  double largest = 0;
  for (size_t i = 0; i < a.q.size(); ++i) largest = std::max(largest, std::abs(a.q[i] - b.q[i]));
  EXPECT_LT(largest, 1e-6) << "joint or base coordinate differs by " << largest;
  EXPECT_NEAR(as_recorded.scale, moved.scale, 1e-12);
}

// The calibration frame's heights are the converter's rest pose, not the take's floor: the motion is moved
// onto its planted soles. Checked with an FK written from the URDF alone: over the source's contact frames,
// the median lowest point of the planted soles (G1's sole points from its map) is on the floor.
TEST_F(CalibrationStance, PlantedSolesAreOnTheFloor) {
  RetargetSummary summary;
  const MotionData motion = Retarget(walk_, map_, &summary);
  bool noted = false;
  for (const std::string& note : summary.notes) noted = noted || note.find("onto the planted soles") != std::string::npos;
  EXPECT_TRUE(noted);
  const testing::IndependentFk fk(testing::SourcePath(testing::kG1Urdf));
  const std::vector<Eigen::Vector3d> sole = {{-0.05, 0.025, -0.035}, {-0.05, -0.025, -0.035}, {0.12, 0.03, -0.035}, {0.12, -0.03, -0.035}};
  const char* links[] = {"left_ankle_roll_link", "right_ankle_roll_link"};
  ASSERT_EQ(motion.contact_feet.size(), 2u);
  const size_t nq = motion.coordinate_names.size(), feet = motion.contact_feet.size();
  std::vector<double> planted;
  for (size_t t = 0; t < motion.time_s.size(); ++t) {
    const auto poses = fk.poses(motion.coordinate_names, &motion.q[t * nq], true);
    for (size_t f = 0; f < feet; ++f) {
      if (!motion.contact[t * feet + f]) continue;
      const size_t side = motion.contact_feet[f] == "left" ? 0 : 1;
      double lowest = std::numeric_limits<double>::infinity();
      for (const Eigen::Vector3d& point : sole) lowest = std::min(lowest, (poses.at(links[side]) * point).z());
      planted.push_back(lowest);
    }
  }
  ASSERT_GT(planted.size(), 100u);
  EXPECT_NEAR(NearestRankPercentile(planted, 0.5), 0.0, 1e-3);
}

}  // namespace
}  // namespace syn
