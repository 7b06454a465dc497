// The stature measured in a capture: the vertical extent of its bodies in its calibration frame, else of its
// markers and bodies at the first frame with data.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>

#include "common/error.h"
#include "stages/human/capture_stature.h"

namespace syn {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

// Two frames, two markers and one body; frame 0 has no data at all.
MarkerData Capture(double marker_top, double marker_bottom, double body_z) {
  MarkerData capture;
  capture.time_s = {0.0, 0.01};
  capture.labels = {"HEAD", "TOE"};
  capture.points = {kNaN, kNaN, kNaN, kNaN, kNaN, kNaN,  // frame 0
                    0.1, 0.0, marker_top, 0.2, 0.1, marker_bottom};
  capture.bodies = {"Hips"};
  capture.body_pose = {kNaN, kNaN, kNaN, 1, 0, 0, 0,  // frame 0
                       0.0, 0.0, body_z, 1, 0, 0, 0};
  return capture;
}

TEST(CaptureStature, IsTheVerticalExtentAtTheFirstFrameWithData) {
  const CaptureStature stature = StatureFromCapture(Capture(1.80, 0.05, 0.95), "walk.markers.h5");
  EXPECT_NEAR(stature.height, 1.75, 1e-12);
  EXPECT_EQ(stature.frame, 1);
  // A body below every marker counts too.
  EXPECT_NEAR(StatureFromCapture(Capture(1.80, 0.05, -0.02), "x").height, 1.82, 1e-12);
}

// A calibration frame (standing straight, kept aside by syn-ingest) is measured instead of the take.
TEST(CaptureStature, TheCalibrationFrameWinsOverTheTake) {
  MarkerData capture = Capture(1.80, 0.05, 0.95);
  capture.bodies = {"Hips", "Head"};
  capture.body_pose = {kNaN, kNaN, kNaN, 1, 0, 0, 0, kNaN, kNaN, kNaN, 1, 0, 0, 0,
                       0.0,  0.0,  0.95, 1, 0, 0, 0, 0.0,  0.0,  1.5,  1, 0, 0, 0};
  capture.calibration_body_pose = {0.0, 0.0, 0.02, 1, 0, 0, 0, 0.0, 0.0, 1.86, 1, 0, 0, 0};
  const CaptureStature stature = StatureFromCapture(capture, "walk.markers.h5");
  EXPECT_NEAR(stature.height, 1.84, 1e-12);
  EXPECT_EQ(stature.frame, -1);
  capture.calibration_body_pose = {0.0, 0.0, 0.02, 1, 0, 0, 0, 0.0, 0.0, 18.6, 1, 0, 0, 0};
  try {
    (void)StatureFromCapture(capture, "cm.markers.h5");
    FAIL() << "expected an error";
  } catch (const DataError& error) {
    EXPECT_NE(std::string(error.what()).find("calibration frame"), std::string::npos) << error.what();
  }
}

TEST(CaptureStature, NoAdultExtentNamesFileAndFrame) {
  try {
    (void)StatureFromCapture(Capture(18.0, 0.5, 9.0), "cm.markers.h5");  // centimetres taken as metres
    FAIL() << "expected an error";
  } catch (const DataError& error) {
    EXPECT_NE(std::string(error.what()).find("cm.markers.h5"), std::string::npos) << error.what();
    EXPECT_NE(std::string(error.what()).find("frame 1"), std::string::npos) << error.what();
  }
  MarkerData empty = Capture(1.8, 0.0, 1.0);
  empty.time_s.resize(1);
  EXPECT_THROW((void)StatureFromCapture(empty, "empty.markers.h5"), DataError);
}

}  // namespace
}  // namespace syn
