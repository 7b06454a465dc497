// Ground truth for syn-retarget: a smooth joint trajectory of G1 within its
// limits, turned into landmark targets by forward kinematics (scale 1, the
// same robot), must come back.
#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "common/intermediate_file.h"
#include "common/markers_file.h"
#include "common/model.h"
#include "stages/retarget/retarget.h"
#include "common/robot_map.h"
#include "tests/support/shared_data.h"
#include "tests/support/standing_pose.h"

namespace syn {
namespace {

namespace fs = std::filesystem;

class RetargetGroundTruth : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("syn_retarget_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    urdf_ = testing::SourcePath("datasets/robots/unitree_g1/g1_29dof.urdf");
    map_path_ = testing::SourcePath("manifests/robots/g1.toml");
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_;
  std::string urdf_, map_path_;
};

TEST_F(RetargetGroundTruth, SmoothG1TrajectoryIsRecovered) {
  const Model model = Model::Load(urdf_);
  const RobotMap map = LoadRobotMap(map_path_);
  // The reference stance as the robot map defines it: zero pose, soles on the ground.
  const Eigen::VectorXd q_ref = testing::StandingZeroPose(model, map);
  Workspace workspace(model);

  // q(t) = q_ref + smooth sines that start at zero, kept inside the joint limits.
  const int frames = 240;
  const double rate = 120.0;
  std::vector<Eigen::VectorXd> truth;
  for (int t = 0; t < frames; ++t) {
    const double time = t / rate;
    Eigen::VectorXd q = q_ref;
    for (int i = 7; i < model.nq(); ++i) {
      const double low = model.qLower()[i], high = model.qUpper()[i];
      const double amplitude = 0.25 * std::min(high - q_ref[i], q_ref[i] - low);
      q[i] = q_ref[i] + amplitude * std::sin(2 * M_PI * (0.3 + 0.05 * (i % 7)) * time);
    }
    const Eigen::Quaterniond base(Eigen::AngleAxisd(0.3 * std::sin(2 * M_PI * 0.2 * time), Eigen::Vector3d::UnitZ()) *
                                  Eigen::AngleAxisd(0.1 * std::sin(2 * M_PI * 0.4 * time), Eigen::Vector3d::UnitY()));
    q.head<4>() << base.w(), base.x(), base.y(), base.z();
    q[4] += 0.4 * time;
    q[6] += 0.05 * std::sin(2 * M_PI * 1.0 * time);
    truth.push_back(q);
  }

  // Landmarks = the task links' poses, as capture bodies named after the landmarks.
  MarkerData capture;
  capture.rate_hz = rate;
  std::string markerset = "name = \"truth\"\n";
  for (const RobotTask& task : map.tasks) {
    capture.bodies.push_back(task.landmark);
    capture.body_parents.push_back("");
    markerset += "[[landmark]]\nname = \"" + task.landmark + "\"\nbody = \"" + task.landmark + "\"\n";
  }
  for (int t = 0; t < frames; ++t) {
    capture.time_s.push_back(t / rate);
    workspace.setQ(truth[static_cast<size_t>(t)]);
    for (const RobotTask& task : map.tasks) {
      const Eigen::Isometry3d pose = workspace.findLinkPose(model.findLinkIndex(task.link));
      const Eigen::Quaterniond rotation(pose.linear());
      capture.body_pose.insert(capture.body_pose.end(), {pose.translation().x(), pose.translation().y(),
                                                         pose.translation().z(), rotation.w(), rotation.x(),
                                                         rotation.y(), rotation.z()});
    }
  }
  const std::string markers = (dir_ / "truth.markers.h5").string();
  {
    Provenance provenance{kMarkersSchema, kMarkersSchemaVersion, "test", {}, nlohmann::json::array()};
    IntermediateWriter writer(markers, provenance);
    WriteMarkerData(writer, capture);
    writer.commit();
  }
  std::ofstream((dir_ / "truth.toml").string()) << markerset;

  RetargetOptions options;
  options.model = urdf_;
  options.robot_map = map_path_;
  options.markerset = (dir_ / "truth.toml").string();
  options.scale = 1.0;
  // Frame 0 is the robot's reference stance itself, which a same-robot retarget states with --reference-time
  // (otherwise the limbs are measured from their median offsets to the pelvis over the take).
  options.reference_time = 0.0;
  // The synthetic trajectory swings its feet through the floor; contact enforcement would (rightly) lift
  // them. This test is about the IK and the refinement recovering the joints, so the motion stays as tracked.
  options.enforce_contacts = false;
  RetargetSummary summary;
  const MotionData motion = RetargetFile(markers, options, &summary);
  ASSERT_EQ(motion.frames(), frames);

  // Compare every task link's pose.
  double position_squares = 0, angle_squares = 0;
  int samples = 0;
  Workspace check(model);
  for (int t = 0; t < frames; ++t) {
    const Eigen::VectorXd q = Eigen::Map<const Eigen::VectorXd>(&motion.q[static_cast<size_t>(t * model.nq())], model.nq());
    for (const RobotTask& task : map.tasks) {
      const int link = model.findLinkIndex(task.link);
      check.setQ(q);
      const Eigen::Isometry3d got = check.findLinkPose(link);
      check.setQ(truth[static_cast<size_t>(t)]);
      const Eigen::Isometry3d want = check.findLinkPose(link);
      position_squares += (got.translation() - want.translation()).squaredNorm();
      angle_squares += std::pow(Eigen::AngleAxisd(got.linear() * want.linear().transpose()).angle(), 2);
      ++samples;
    }
  }
  const double position_rms = std::sqrt(position_squares / samples);
  const double angle_rms_deg = std::sqrt(angle_squares / samples) * 180 / M_PI;
  EXPECT_LT(position_rms, 1e-3) << "m";
  EXPECT_LT(angle_rms_deg, 0.5) << "deg";
  std::cout << "recovered: position RMS " << position_rms * 1000 << " mm, angle RMS " << angle_rms_deg << " deg; "
            << summary.BriefReport() << "\n";
  RecordProperty("position_rms_m", std::to_string(position_rms));
  RecordProperty("angle_rms_deg", std::to_string(angle_rms_deg));

  // Inverse-dynamics torques reproduce the accelerations under forward dynamics.
  double worst = 0;
  Eigen::VectorXd udot;
  for (int t = 0; t < frames; t += 7) {
    const int nq = model.nq(), nu = model.nu();
    check.setQ(Eigen::Map<const Eigen::VectorXd>(&motion.q[static_cast<size_t>(t * nq)], nq));
    check.setU(Eigen::Map<const Eigen::VectorXd>(&motion.u[static_cast<size_t>(t * nu)], nu));
    check.calcForwardDynamics(Eigen::Map<const Eigen::VectorXd>(&motion.tau[static_cast<size_t>(t * nu)], nu), udot);
    worst = std::max(worst, (udot - Eigen::Map<const Eigen::VectorXd>(&motion.udot[static_cast<size_t>(t * nu)], nu))
                                .cwiseAbs()
                                .maxCoeff());
  }
  EXPECT_LT(worst, 1e-6);
}

}  // namespace
}  // namespace syn
