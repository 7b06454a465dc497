// syn-evaluate's fast path (Workspace::calcMassTimesAt / calcDynamicsAt, reconstructions over threads)
// against the straightforward reference path (Simbody's setQ, multiplyByM, inverse dynamics, one
// thread), on real trials at the paper's protocol: 1 kHz grid, same seeds.
#include <gtest/gtest.h>

#include <cmath>
#include <string>

#include "common/model.h"
#include "stages/evaluate/evaluate.h"
#include "stages/evaluate/worker_threads.h"
#include "common/robot_map.h"
#include "stages/segment/segmentation.h"
#include "stages/synergies/synergies.h"
#include "tests/support/demo_motion.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

// Every number of `fast` within `tolerance` (relative) of the same number of `reference`; every other
// value equal. Returns how many numbers were compared.
int ExpectSameMetrics(const nlohmann::json& reference, const nlohmann::json& fast, double tolerance,
                      const std::string& path) {
  EXPECT_EQ(reference.type(), fast.type()) << path;
  if (reference.type() != fast.type()) return 0;
  int compared = 0;
  if (reference.is_object()) {
    EXPECT_EQ(reference.size(), fast.size()) << path;
    for (const auto& [key, value] : reference.items()) {
      if (!fast.contains(key)) {
        ADD_FAILURE() << path << "/" << key << " missing";
        continue;
      }
      compared += ExpectSameMetrics(value, fast[key], tolerance, path + "/" + key);
    }
  } else if (reference.is_array()) {
    EXPECT_EQ(reference.size(), fast.size()) << path;
    for (size_t i = 0; i < std::min(reference.size(), fast.size()); ++i) {
      compared += ExpectSameMetrics(reference[i], fast[i], tolerance, path + "/" + std::to_string(i));
    }
  } else if (reference.is_number_float()) {
    const double a = reference.get<double>(), b = fast.get<double>();
    EXPECT_LE(std::abs(a - b), tolerance * std::max(std::abs(a), std::abs(b))) << path << ": " << a << " vs " << b;
    ++compared;
  } else {
    EXPECT_EQ(reference, fast) << path;
  }
  return compared;
}

class FastEvaluatePath : public ::testing::TestWithParam<const char*> {};

TEST_P(FastEvaluatePath, GivesTheReferencePathsMetricsOnARealTrial) {
  const MotionData& motion = testing::DemoMotionOnG1(GetParam());
  const Model model = Model::Load(testing::SourcePath(testing::kG1Urdf));
  const std::vector<FootPoints> feet = FeetOnModel(LoadRobotMap(testing::SourcePath(testing::kG1Map)), model);
  const TrialSynergies synergies = ComputeTrialSynergies(motion, SegmentMotion(motion, model, {}).boundaries, {});
  ASSERT_GE(synergies.segments.size(), 2u);
  EvaluateOptions reference;  // the paper's 1 kHz and seed; fewer samples keep the reference path short
  reference.monte_carlo.samples = 12;
  reference.momentum = MomentumOperator::kSimbody;
  reference.threads = 1;
  EvaluateOptions fast = reference;
  fast.momentum = MomentumOperator::kTree;
  fast.threads = 2;
  const nlohmann::json expected = EvaluateMotion(motion, model, feet, &synergies, reference, "reference");
  const nlohmann::json actual = EvaluateMotion(motion, model, feet, &synergies, fast, "fast");
  ASSERT_TRUE(expected.contains("monte_carlo") && expected["monte_carlo"].contains("mean_relative_change_delta_p"));
  const int compared = ExpectSameMetrics(expected, actual, 1e-9, "");
  // Trial, per segment: stored, original, rank k and the perturbed spreads — far more than a handful.
  EXPECT_GT(compared, 40 * static_cast<int>(synergies.segments.size()));
}

INSTANTIATE_TEST_SUITE_P(DemoTrials, FastEvaluatePath, ::testing::Values("02_01", "13_11"));

TEST(FastEvaluatePath, AnyThreadCountGivesByteIdenticalOutput) {
  const MotionData& motion = testing::DemoMotionOnG1("02_01");
  const Model model = Model::Load(testing::SourcePath(testing::kG1Urdf));
  const std::vector<FootPoints> feet = FeetOnModel(LoadRobotMap(testing::SourcePath(testing::kG1Map)), model);
  const TrialSynergies synergies = ComputeTrialSynergies(motion, SegmentMotion(motion, model, {}).boundaries, {});
  EvaluateOptions options;
  options.monte_carlo.samples = 20;
  options.threads = 1;
  const std::string one = EvaluateMotion(motion, model, feet, &synergies, options, "s").dump(1);
  options.threads = 3;
  const std::string three = EvaluateMotion(motion, model, feet, &synergies, options, "s").dump(1);
  EXPECT_EQ(one, three);
  options.monte_carlo.seed = 2;  // and the comparison can fail: another seed changes the text
  EXPECT_NE(one, EvaluateMotion(motion, model, feet, &synergies, options, "s").dump(1));
}

TEST(WorkerThreads, DefaultCountLeavesMakesJobsTheirCores) {
  EXPECT_EQ(DefaultThreadCount("", "", 8), 8);                                   // not under make
  EXPECT_EQ(DefaultThreadCount("", "", 0), 1);                                   // cores unknown
  EXPECT_EQ(DefaultThreadCount("3", " -j2 --jobserver-auth=3,4", 8), 3);         // SYN_THREADS wins
  EXPECT_EQ(DefaultThreadCount("", " -j2 --jobserver-auth=3,4", 2), 1);          // make -j2 on 2 cores
  EXPECT_EQ(DefaultThreadCount("", "s -j4 --jobserver-auth=fifo:/tmp/x", 16), 4);
  EXPECT_EQ(DefaultThreadCount("", "s", 2), 2);                                  // make without -j
  EXPECT_EQ(DefaultThreadCount("", "-j --jobserver-auth=3,4", 8), 1);            // unlimited jobs
  EXPECT_EQ(DefaultThreadCount("zero", " -- X=-j8", 4), 4);                      // junk and assignments ignored
}

TEST(WorkerThreads, EveryTaskRunsOnceAndTheFirstErrorIsRethrown) {
  std::vector<int> runs(1000, 0);
  RunTasks(1000, 3, [&](int worker, int64_t task) {
    EXPECT_LT(worker, 3);
    ++runs[static_cast<size_t>(task)];
  });
  EXPECT_EQ(std::count(runs.begin(), runs.end(), 1), 1000);
  EXPECT_THROW(RunTasks(50, 2, [](int, int64_t task) {
                 if (task == 17) throw std::runtime_error("task 17");
               }),
               std::runtime_error);
}

}  // namespace
}  // namespace syn
