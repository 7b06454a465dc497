#include "stages/retarget/landmarks.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <random>

#include "common/error.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

// Plug-in Gait pelvis markers in the pelvis frame (x forward, y left, z up).
const std::vector<std::pair<std::string, Eigen::Vector3d>> kPelvisMarkers = {
    {"LASI", {0.10, 0.12, 0.0}}, {"RASI", {0.10, -0.12, 0.0}}, {"LPSI", {-0.08, 0.05, 0.0}}, {"RPSI", {-0.08, -0.05, 0.0}}};

MarkerSet PelvisOnlySet() {
  return ParseMarkerSet(R"(
name = "pelvis-only"
[[landmark]]
name = "pelvis"
origin = ["LASI|LFWT", "RASI|RFWT", "LPSI|LBWT", "RPSI|RBWT"]
primary = "y"
y = { from = ["RASI|RFWT", "RPSI|RBWT"], to = ["LASI|LFWT", "LPSI|LBWT"] }
x = { from = ["LPSI|LBWT", "RPSI|RBWT"], to = ["LASI|LFWT", "RASI|RFWT"] }
)",
                        "pelvis-only.toml");
}

MarkerData PelvisCapture(const std::vector<Eigen::Isometry3d>& poses, const std::string& prefix,
                         bool back_waist_names) {
  MarkerData capture;
  capture.rate_hz = 100;
  for (const auto& [name, local] : kPelvisMarkers) {
    std::string label = name;
    if (back_waist_names && name == "LPSI") label = "LBWT";
    if (back_waist_names && name == "RPSI") label = "RBWT";
    capture.labels.push_back(prefix + label);
  }
  for (size_t t = 0; t < poses.size(); ++t) {
    capture.time_s.push_back(static_cast<double>(t) / capture.rate_hz);
    for (const auto& [name, local] : kPelvisMarkers) {
      const Eigen::Vector3d world = poses[t] * local;
      capture.points.insert(capture.points.end(), {world.x(), world.y(), world.z()});
    }
  }
  return capture;
}

std::vector<Eigen::Isometry3d> RandomPoses(int count, unsigned seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  std::vector<Eigen::Isometry3d> poses;
  for (int i = 0; i < count; ++i) {
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    pose.linear() = Eigen::Quaterniond(Eigen::Vector4d(uniform(random), uniform(random), uniform(random),
                                                       uniform(random)).normalized())
                        .toRotationMatrix();
    pose.translation() = Eigen::Vector3d(uniform(random), uniform(random), 1.0 + uniform(random));
    poses.push_back(pose);
  }
  return poses;
}

TEST(Landmarks, MarkerFrameFollowsTheRigidSegmentExactly) {
  const auto poses = RandomPoses(20, 7);
  const MarkerData capture = PelvisCapture(poses, "", false);
  const LandmarkTrajectories landmarks = ComputeLandmarks(capture, PelvisOnlySet(), "synthetic");
  ASSERT_EQ(landmarks.count(), 1);
  EXPECT_TRUE(landmarks.has_orientation[0]);
  // Independent expectation: origin = pose * mean(local markers); axes = the pose's axes, because the
  // markers are left/right symmetric about the pelvis x–z plane.
  Eigen::Vector3d local_mean = Eigen::Vector3d::Zero();
  for (const auto& marker : kPelvisMarkers) local_mean += marker.second / 4.0;
  for (size_t t = 0; t < poses.size(); ++t) {
    const double* pose = &landmarks.pose[t * 7];
    const Eigen::Vector3d origin(pose[0], pose[1], pose[2]);
    EXPECT_LT((origin - poses[t] * local_mean).norm(), 1e-12);
    const Eigen::Quaterniond q(pose[3], pose[4], pose[5], pose[6]);
    EXPECT_LT(q.angularDistance(Eigen::Quaterniond(poses[t].linear())), 1e-9) << "frame " << t;
  }
}

TEST(Landmarks, AlternatesAndSubjectPrefixesResolve) {
  const MarkerData capture = PelvisCapture(RandomPoses(3, 11), "Male:", /*back_waist_names=*/true);
  const LandmarkTrajectories landmarks = ComputeLandmarks(capture, PelvisOnlySet(), "cmu-like");
  EXPECT_NE(landmarks.sources[0].find("Male:LBWT"), std::string::npos) << landmarks.sources[0];
  EXPECT_TRUE(std::isfinite(landmarks.pose[3]));
}

TEST(Landmarks, AMissingMarkerMakesOnlyThatFrameMissing) {
  MarkerData capture = PelvisCapture(RandomPoses(5, 3), "", false);
  capture.points[(2 * 4 + 1) * 3 + 0] = std::nan("");  // RASI x in frame 2
  const LandmarkTrajectories landmarks = ComputeLandmarks(capture, PelvisOnlySet(), "gappy");
  for (int t = 0; t < 5; ++t) {
    for (int k = 0; k < 7; ++k) {
      EXPECT_EQ(std::isnan(landmarks.pose[t * 7 + k]), t == 2) << "frame " << t << " value " << k;
    }
  }
}

TEST(Landmarks, UnknownMarkerNamesTheMarkerSetLineAndTheFileLabels) {
  MarkerData capture = PelvisCapture(RandomPoses(1, 5), "", false);
  capture.labels[0] = "XASI";
  try {
    (void)ComputeLandmarks(capture, PelvisOnlySet(), "trial.c3d");
    FAIL() << "a missing marker was not reported";
  } catch (const DataError& error) {
    const std::string message = error.what();
    EXPECT_NE(message.find("pelvis-only.toml:3"), std::string::npos) << message;
    EXPECT_NE(message.find("LASI|LFWT"), std::string::npos) << message;
    EXPECT_NE(message.find("XASI, RASI"), std::string::npos) << message;
  }
}

TEST(MarkerSet, BundledSetsParse) {
  for (const char* name : {"plugin-gait", "cmu-bvh", "humanml3d22"}) {
    const MarkerSet set = LoadMarkerSet(testing::SourcePath(std::string("manifests/markersets/") + name + ".toml"));
    EXPECT_EQ(set.name, name);
    // Every Table I landmark; the shoulders, hips and knees where the format names them (a Plug-in Gait
    // capture need not carry LSHO/RSHO, so that set leaves them to the retargeter's anthropometric estimate).
    std::vector<std::string> names;
    for (const LandmarkDefinition& landmark : set.landmarks) names.push_back(landmark.name);
    const size_t expected = std::string(name) == "plugin-gait" ? 9 : kLandmarkNames.size();
    for (size_t i = 0; i < expected; ++i) {
      EXPECT_NE(std::find(names.begin(), names.end(), kLandmarkNames[i]), names.end()) << name << ": " << kLandmarkNames[i];
    }
    EXPECT_EQ(names.size(), expected) << name;
  }
}

TEST(MarkerSet, MistakesAreReportedAtTheirLine) {
  const auto line_of = [](const std::string& text) {
    try {
      (void)ParseMarkerSet(text, "bad.toml");
    } catch (const DataError& error) {
      return error.where().line;
    }
    return int64_t{-1};
  };
  EXPECT_EQ(line_of("name = \"s\"\n[[landmark]]\nname = \"nose\"\norigin = [\"A\"]\n"), 2);  // unknown landmark
  EXPECT_EQ(line_of("name = \"s\"\n[[landmark]]\nname = \"head\"\norigin = [\"A\"]\nwidth = 3\n"), 5);
  EXPECT_EQ(line_of("name = \"s\"\n[[landmark]]\nname = \"head\"\norigin = [\"A\"]\nprimary = \"x\"\n"
                    "x = { from = [\"A\"], to = [\"B\"] }\n"),
            2);  // one axis only
  EXPECT_EQ(line_of("name = \"s\"\n[[landmark\n"), 2);  // TOML syntax
}

}  // namespace
}  // namespace syn
