#include "stages/ingest/capture_normalization.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>

#include "stages/ingest/capture_format.h"

namespace syn {
namespace {

MarkerData YUpMillimetres() {
  MarkerData data;
  data.rate_hz = 100;
  data.time_s = {0.0};
  data.labels = {"Male:LFHD", "Male:LFHD", "RFHD"};
  data.points = {1, 2, 3, 4, 5, 6, std::nan(""), 0, 0};
  data.bodies = {"hip"};
  data.body_parents = {""};
  data.body_pose = {10, 20, 30, 1, 0, 0, 0};  // identity orientation
  data.calibration_body_pose = {10, 20, 30, 1, 0, 0, 0};
  data.length_unit_to_m = 0.001;
  data.up_axis = 'y';
  return data;
}

TEST(CaptureNormalization, YUpMillimetresBecomeZUpMetres) {
  MarkerData data = YUpMillimetres();
  NormalizeCapture(data, {});
  // (x, y, z) -> (z, x, y), then mm -> m.
  EXPECT_DOUBLE_EQ(data.points[0], 0.003);
  EXPECT_DOUBLE_EQ(data.points[1], 0.001);
  EXPECT_DOUBLE_EQ(data.points[2], 0.002);
  EXPECT_TRUE(std::isnan(data.points[6]));  // missing stays missing, not zero
  EXPECT_DOUBLE_EQ(data.body_pose[0], 0.030);
  EXPECT_DOUBLE_EQ(data.body_pose[2], 0.020);
  // The body's own +Y axis pointed up in the file; it must point along +Z now.
  const Eigen::Quaterniond q(data.body_pose[3], data.body_pose[4], data.body_pose[5], data.body_pose[6]);
  EXPECT_NEAR((q * Eigen::Vector3d::UnitY() - Eigen::Vector3d::UnitZ()).norm(), 0.0, 1e-12);
  // A proper rotation: handedness kept.
  EXPECT_NEAR(q.toRotationMatrix().determinant(), 1.0, 1e-12);
  // The calibration stance is converted exactly as the take is.
  for (size_t i = 0; i < 7; ++i) EXPECT_DOUBLE_EQ(data.calibration_body_pose[i], data.body_pose[i]) << i;
  EXPECT_EQ(data.up_axis, 'z');
  EXPECT_EQ(data.length_unit_to_m, 1.0);
}

TEST(CaptureNormalization, DuplicateLabelsAreRenamedWithAWarning) {
  MarkerData data = YUpMillimetres();
  NormalizeCapture(data, {});
  EXPECT_EQ(data.labels, (std::vector<std::string>{"Male:LFHD", "Male:LFHD_2", "RFHD"}));
  ASSERT_FALSE(data.warnings.empty());
  EXPECT_NE(data.warnings.back().find("duplicate"), std::string::npos);
}

TEST(CaptureNormalization, PrefixesCanBeStripped) {
  MarkerData data = YUpMillimetres();
  NormalizationOptions options;
  options.strip_prefix = true;
  NormalizeCapture(data, options);
  EXPECT_EQ(data.labels, (std::vector<std::string>{"LFHD", "LFHD_2", "RFHD"}));
}

TEST(CaptureNormalization, OverridesWinOverTheFile) {
  MarkerData data = YUpMillimetres();
  NormalizationOptions options;
  options.up_axis = 'z';
  options.length_unit_to_m = 1.0;
  options.rate_hz = 50;
  NormalizeCapture(data, options);
  EXPECT_DOUBLE_EQ(data.points[0], 1.0);
  EXPECT_DOUBLE_EQ(data.points[2], 3.0);
  EXPECT_EQ(data.rate_hz, 50);
}

TEST(CaptureFormat, DetectedFromContent) {
  std::string c3d(512, '\0');
  c3d[0] = 2;
  c3d[1] = 0x50;
  EXPECT_EQ(DetectCaptureFormat(c3d), CaptureFormat::kC3d);
  EXPECT_EQ(DetectCaptureFormat("PathFileType\t4\t(X/Y/Z)\tfile.trc"), CaptureFormat::kTrc);
  EXPECT_EQ(DetectCaptureFormat("Format Version,1.23,Take Name,x"), CaptureFormat::kMotiveCsv);
  EXPECT_EQ(DetectCaptureFormat("HIERARCHY\nROOT Hips"), CaptureFormat::kBvh);
  EXPECT_EQ(DetectCaptureFormat("\x93NUMPY\x01\x00"), CaptureFormat::kNpy);
  EXPECT_EQ(DetectCaptureFormat("\xEF\xBB\xBF" "Format Version,1.21"), CaptureFormat::kMotiveCsv);
  EXPECT_FALSE(DetectCaptureFormat("time,x,y,z\n").has_value());
  EXPECT_EQ(CaptureFormatFromExtension("a/B.C3D"), CaptureFormat::kC3d);
  EXPECT_EQ(CaptureFormatFromName("motive-csv"), CaptureFormat::kMotiveCsv);
}

}  // namespace
}  // namespace syn
