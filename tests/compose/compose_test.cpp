#include <gtest/gtest.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>

#include "common/error.h"
#include "common/motion_integration.h"
#include "common/row_major.h"
#include "stages/compose/compose_script.h"
#include "stages/compose/composer.h"
#include "stages/export/motion_export.h"
#include "stages/library/style_library.h"
#include "stages/segment/segmentation.h"
#include "stages/synergies/synergies.h"
#include "tests/support/demo_motion.h"
#include "tests/support/run_command.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

namespace fs = std::filesystem;

// A library of the demo's modern-dance trial and its walk on G1, written once for the suite (the walk's
// segments give the exactness tests one that plays within the joint limits at rank 3; since the feet's
// neutral reference none of the dance's does).
class ComposeTest : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    model_ = new Model(Model::Load(testing::SourcePath(testing::kG1Urdf)));
    std::vector<LabelledTrial> trials;
    for (const auto& [id, style] : {std::pair<const char*, const char*>{"05_02", "modern"}, {"02_01", "walk"}}) {
      const MotionData& motion = testing::DemoMotionOnG1(id);
      LabelledTrial trial;
      trial.labels.trial = id;
      trial.labels.style = style;
      trial.synergies = ComputeTrialSynergies(motion, SegmentMotion(motion, *model_, {}).boundaries,
                                              SynergyOptions{3, VelocitySet::kAll, trial.labels});
      trials.push_back(std::move(trial));
    }
    dir_ = new std::string(fs::temp_directory_path() / ("syn_compose_" + std::to_string(::getpid())));
    fs::create_directories(*dir_);
    const std::string path = *dir_ + "/library.h5";
    IntermediateWriter writer(path, {kLibrarySchema, kLibrarySchemaVersion, "test", {}, nlohmann::json::array()});
    WriteLibrary(writer, BuildLibrary(trials, {"05_02", "02_01"}, 3));
    writer.commit();
    library_ = new LibraryReader(path);
  }
  static void TearDownTestSuite() {
    fs::remove_all(*dir_);
    delete library_;
    delete model_;
    delete dir_;
  }

  static ComposeScript OneStep(const std::string& synergy) {
    ComposeScript script;
    script.file = "test.toml";
    script.model = testing::SourcePath(testing::kG1Urdf);
    ComposeStep step;
    step.synergy = synergy;
    step.line = 3;
    script.steps.push_back(step);
    return script;
  }
  static ComposedMotion Compose(const ComposeScript& script) {
    const Composer composer(script, *library_, *model_, Composer::StartPose(script, *library_));
    return composer.compose();
  }
  // The first segment that plays within G1's limits on its own (the test is about exactness, not limits).
  static std::string QuietSynergy() {
    for (const std::string& name : library_->synergyNames()) {
      if (Compose(OneStep(name)).warnings.empty()) return name;
    }
    return {};
  }

  static Model* model_;
  static LibraryReader* library_;
  static std::string* dir_;
};
Model* ComposeTest::model_ = nullptr;
LibraryReader* ComposeTest::library_ = nullptr;
std::string* ComposeTest::dir_ = nullptr;

TEST_F(ComposeTest, OneSynergyAtItsOwnDurationIsItsRankKReconstruction) {
  const std::string name = QuietSynergy();
  ASSERT_FALSE(name.empty()) << "every demo segment hits a limit";
  const ComposedMotion composed = Compose(OneStep(name));
  const TrialSynergies::Segment segment = library_->read(name).segment;
  const Eigen::VectorXd q0 = Eigen::Map<const Eigen::VectorXd>(segment.q0.data(), model_->nq());
  const Eigen::VectorXd times = Eigen::Map<const Eigen::VectorXd>(segment.times.data(), static_cast<Eigen::Index>(segment.times.size()));
  Eigen::MatrixXd q, u;
  IntegrateVelocities(true, q0, times, ReconstructVelocities(segment.synergies, segment.synergies.singular_values),
                      BaseVelocityFrame::kHeading, q, u);
  ASSERT_EQ(composed.motion.frames(), q.rows());
  const Eigen::MatrixXd composed_q = MatrixFromRowMajor({{composed.motion.frames(), model_->nq()}, composed.motion.q});
  const Eigen::MatrixXd composed_u = MatrixFromRowMajor({{composed.motion.frames(), model_->nu()}, composed.motion.u});
  EXPECT_LT((composed_q - q).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((composed_u - u).cwiseAbs().maxCoeff(), 1e-9);
}

TEST_F(ComposeTest, HalvingTheDurationKeepsTheEndPoseAndDoublesThePeakVelocity) {
  const std::string name = QuietSynergy();
  ASSERT_FALSE(name.empty());
  ComposeScript script = OneStep(name);
  const ComposedMotion original = Compose(script);
  const TrialSynergies::Segment segment = library_->read(name).segment;
  script.steps[0].duration = 0.5 * (segment.times.back() - segment.times.front());
  const ComposedMotion fast = Compose(script);
  ASSERT_TRUE(fast.warnings.empty()) << fast.warnings.front();
  const int64_t nq = model_->nq(), nu = model_->nu();
  const Eigen::Map<const Eigen::VectorXd> end_original(&original.motion.q[static_cast<size_t>((original.motion.frames() - 1) * nq)], nq);
  const Eigen::Map<const Eigen::VectorXd> end_fast(&fast.motion.q[static_cast<size_t>((fast.motion.frames() - 1) * nq)], nq);
  EXPECT_LT((end_original - end_fast).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_NEAR(fast.motion.time_s.back(), 0.5 * original.motion.time_s.back(), 1e-12);
  // Peak joint speed (the base's is turned by the heading, so compare the joints).
  auto peak = [&](const MotionData& motion) {
    double largest = 0;
    for (int64_t t = 0; t < motion.frames(); ++t) {
      for (int64_t v = 6; v < nu; ++v) largest = std::max(largest, std::abs(motion.u[static_cast<size_t>(t * nu + v)]));
    }
    return largest;
  };
  EXPECT_NEAR(peak(fast.motion) / peak(original.motion), 2.0, 1e-9);
}

// Velocity continuity at the cross-fade window edges and at the step boundary. A quantity that is
// continuous at t differs across [t − h, t + h] by O(h), so shrinking h tenfold shrinks the difference about
// tenfold; across a discontinuity it does not shrink.
TEST_F(ComposeTest, BlendContinuityMatchesTheInterpolation) {
  const std::vector<std::string> names = library_->synergyNames();
  ComposeScript script = OneStep(names[0]);
  script.steps.push_back(script.steps[0]);
  script.steps[1].synergy = names[1];
  const StepScales ones = StepScales::Ones(2, model_->nu());
  // Differences of the velocity (order 0), its slope (1) and its curvature (2) across t, one-sided estimates.
  auto jump = [&](const Composer& composer, double t, int order, double h) {
    Eigen::VectorXd v[5];
    for (int i = 0; i < 5; ++i) {
      v[i].resize(model_->nu());
      composer.velocityAt(t + (i - 2) * h, ones, v[i]);
    }
    if (order == 0) return (v[3] - v[1]).cwiseAbs().maxCoeff();
    if (order == 1) return ((v[4] - v[3]) - (v[1] - v[0])).cwiseAbs().maxCoeff() / h;
    return ((v[4] - 2 * v[3] + v[2]) - (v[2] - 2 * v[1] + v[0])).cwiseAbs().maxCoeff() / (h * h);
  };
  // The smallest shrink factor of the order-k jump over the three critical instants.
  auto shrink = [&](Interpolation interpolation, int order) {
    script.steps[0].interpolation = interpolation;
    script.steps[0].blend = 0.3;
    const Composer composer(script, *library_, *model_, Composer::StartPose(script, *library_));
    const double boundary = composer.boundaries().at(0);
    double smallest = std::numeric_limits<double>::infinity();
    for (double t : {boundary - 0.15, boundary, boundary + 0.15}) {
      const double coarse = jump(composer, t, order, 1e-5), fine = jump(composer, t, order, 1e-6);
      smallest = std::min(smallest, coarse / std::max(fine, 1e-300));
    }
    return smallest;
  };
  EXPECT_LT(shrink(Interpolation::kStep, 0), 2.0);  // the velocity jumps (the pose stays C0)
  EXPECT_GT(shrink(Interpolation::kLinear, 0), 5.0);  // C0 velocity ...
  EXPECT_LT(shrink(Interpolation::kLinear, 1), 2.0);  // ... with a kink at the window edges
  EXPECT_GT(shrink(Interpolation::kCubic, 0), 5.0);
  EXPECT_GT(shrink(Interpolation::kCubic, 1), 5.0);  // C1 ...
  EXPECT_LT(shrink(Interpolation::kCubic, 2), 2.0);  // ... not C2
  EXPECT_GT(shrink(Interpolation::kMinimumJerk, 0), 5.0);
  EXPECT_GT(shrink(Interpolation::kMinimumJerk, 1), 5.0);
  EXPECT_GT(shrink(Interpolation::kMinimumJerk, 2), 5.0);  // C2
}

TEST_F(ComposeTest, LimitViolationsAreScaledAndWarnedNeverClipped) {
  ComposeScript script = OneStep(library_->synergyNames()[0]);
  CoefficientKeyframe loud;
  loud.gains = {6.0, 6.0, 6.0};
  script.steps[0].keyframes = {loud};
  script.steps[0].repetitions = 2;
  const ComposedMotion composed = Compose(script);
  ASSERT_FALSE(composed.warnings.empty());
  EXPECT_NE(composed.warnings[0].find("test.toml:3: step 1"), std::string::npos) << composed.warnings[0];
  EXPECT_NE(composed.warnings[0].find("joint '"), std::string::npos);
  const int64_t nq = model_->nq(), nu = model_->nu();
  for (int64_t t = 0; t < composed.motion.frames(); ++t) {
    for (const ModelJoint& joint : model_->joints()) {
      if (joint.q_index < 0 || joint.type == "free") continue;
      const double q = composed.motion.q[static_cast<size_t>(t * nq + joint.q_index)];
      EXPECT_GE(q, model_->qLower()[joint.q_index] - 1e-8) << joint.name << " frame " << t;
      EXPECT_LE(q, model_->qUpper()[joint.q_index] + 1e-8) << joint.name << " frame " << t;
      EXPECT_LE(std::abs(composed.motion.u[static_cast<size_t>(t * nu + joint.u_index)]), model_->uLimit()[joint.u_index] + 1e-8);
    }
  }
  // Scaled, not clipped: each joint's velocity is the full-scale one times its step factor at every sample
  // (a clipped joint would sit at its limit with zero velocity while the full-scale one moves on).
  ASSERT_EQ(composed.step_scales.rows(), 1);
  EXPECT_LT(composed.step_scales.minCoeff(), 1.0);
  const Composer composer(script, *library_, *model_, Composer::StartPose(script, *library_));
  const StepScales full_scale = StepScales::Ones(1, nu);
  Eigen::VectorXd full(nu);
  int scaled_joints = 0;
  for (const ModelJoint& joint : model_->joints()) {
    if (joint.u_index < 0 || joint.type == "free") continue;
    const double factor = composed.step_scales(0, joint.u_index);
    scaled_joints += factor < 1.0;
    double largest_full = 0;
    for (int64_t t = 0; t < composed.motion.frames(); ++t) {
      composer.velocityAt(composed.motion.time_s[static_cast<size_t>(t)], full_scale, full);
      const double composed_u = composed.motion.u[static_cast<size_t>(t * nu + joint.u_index)];
      largest_full = std::max(largest_full, std::abs(full[joint.u_index]));
      EXPECT_NEAR(composed_u, factor * full[joint.u_index], 1e-9 * (1 + std::abs(full[joint.u_index])))
          << joint.name << " (factor " << factor << ") frame " << t;
    }
    if (factor < 1.0) {
      EXPECT_GT(largest_full, 0.0) << joint.name << " was scaled although it does not move";
    }
  }
  EXPECT_GE(scaled_joints, 1);
}

TEST_F(ComposeTest, AScriptNamingAMissingSynergyFailsAtItsLine) {
  const std::string script = *dir_ + "/missing.toml";
  std::ofstream(script) << "model = \"" << testing::SourcePath(testing::kG1Urdf) << "\"\n\n[[step]]\nsynergy = \"modern/05_02/0\"\n\n"
                        << "[[step]]\nsynergy = \"salsa/60_10/4\"\n";
  const testing::CommandResult result = testing::RunCommand(testing::BinPath("syn-compose") + " " + script + " --library " +
                                                            *dir_ + "/library.h5 -o " + *dir_ + "/out.motion.h5");
  EXPECT_EQ(result.exit_code, 1);
  EXPECT_NE(result.output.find("missing.toml:6: "), std::string::npos) << result.output;
  EXPECT_NE(result.output.find("modern/05_02/0"), std::string::npos) << "the error should list what exists";
  EXPECT_FALSE(fs::exists(*dir_ + "/out.motion.h5"));
  std::ofstream(script) << "model = \"x.urdf\"\n[[step]]\nsynergy = \"a/b/0\"\ntempo = 2\n";
  EXPECT_THROW(
      {
        try {
          (void)LoadComposeScript(script);
        } catch (const DataError& error) {
          EXPECT_NE(std::string(error.what()).find("missing.toml:4: unknown step key 'tempo'"), std::string::npos) << error.what();
          throw;
        }
      },
      DataError);
}

TEST_F(ComposeTest, RobotCsvReadsBackTheSameQAndMotHasOpenSimsHeader) {
  const MotionData& motion = testing::DemoMotionOnG1("05_02");
  const std::string csv = *dir_ + "/g1.csv";
  std::ofstream(csv) << MotionToRobotCsv(motion, *model_);
  const MotionData back = ReadRobotCsv(csv, *model_, 120.0);
  ASSERT_EQ(back.frames(), motion.frames());
  for (size_t i = 0; i < motion.q.size(); ++i) ASSERT_EQ(back.q[i], motion.q[i]) << i;  // shortest round-trip text

  std::istringstream mot(MotionToMot(motion, *model_, "dance"));
  std::vector<std::string> lines;
  for (std::string line; std::getline(mot, line);) lines.push_back(line);
  ASSERT_GT(lines.size(), 8u);
  EXPECT_EQ(lines[0], "dance");
  EXPECT_EQ(lines[1], "version=1");
  EXPECT_EQ(lines[2], "nRows=" + std::to_string(motion.frames()));
  EXPECT_EQ(lines[3], "nColumns=36");  // time + 6 base + 29 joints
  EXPECT_EQ(lines[4], "inDegrees=yes");
  EXPECT_EQ(lines[5], "endheader");
  EXPECT_EQ(std::count(lines[6].begin(), lines[6].end(), '\t'), 35);
  EXPECT_EQ(lines[6].substr(0, 5), "time\t");
  EXPECT_EQ(lines.size(), static_cast<size_t>(motion.frames()) + 7);
}

TEST(RobotCsv, KimodoG1FilesReadAndWriteBackIdentically) {
  SYN_REQUIRE_SHARED("robot_motion/g1_kimodo_walk.csv");
  const Model model = Model::Load(testing::SourcePath(testing::kG1Urdf));
  for (const char* name : {"walk", "dance", "jumpjack"}) {
    const std::string path = testing::SharedPath(std::string("robot_motion/g1_kimodo_") + name + ".csv");
    const MotionData motion = ReadRobotCsv(path, model, 30.0);
    EXPECT_GE(motion.frames(), 120) << name;
    const std::string written = MotionToRobotCsv(motion, model);
    const std::string other = fs::temp_directory_path() / ("syn_kimodo_" + std::to_string(::getpid()) + ".csv");
    std::ofstream(other) << written;
    const MotionData again = ReadRobotCsv(other, model, 30.0);
    fs::remove(other);
    ASSERT_EQ(again.q, motion.q) << name;
    // Root height of a standing G1 pelvis (SOURCES.md: ~0.79 m) lands in base_z.
    EXPECT_NEAR(motion.q[6], 0.78, 0.05) << name;
  }
  const std::string bad = fs::temp_directory_path() / ("syn_bad_" + std::to_string(::getpid()) + ".csv");
  std::ofstream(bad) << "0,0,0.8,1,0,0,0\n";
  try {
    (void)ReadRobotCsv(bad, model, 30.0);
    ADD_FAILURE() << "a 7-column row was accepted";
  } catch (const DataError& error) {
    EXPECT_NE(std::string(error.what()).find(":1: 7 columns; expected 36"), std::string::npos) << error.what();
  }
  fs::remove(bad);
}

}  // namespace
}  // namespace syn
