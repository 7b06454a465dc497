// syn-evaluate throughput on G1 at the paper's 1 kHz: per evaluation frame a
// cubic resample of q and u, Simbody's A·u, and (for every metric) inverse
// dynamics and the foot sole points; the Monte-Carlo samples need A·u only.
// EvaluateStageG1 runs the stage's default workload (the trial with every
// metric, then 100 Monte-Carlo reconstructions of each segment) and counts
// every evaluated frame.
#include <benchmark/benchmark.h>

#include <cmath>

#include "common/model.h"
#include "stages/evaluate/evaluate.h"
#include "stages/evaluate/motion_metrics.h"
#include "stages/segment/segmentation.h"
#include "stages/synergies/synergies.h"

namespace syn {
namespace {

void EvaluateG1(benchmark::State& state) {
  const bool all_metrics = state.range(0) != 0;
  const std::string root = SYN_SOURCE_DIR;
  const Model model = Model::Load(root + "/datasets/robots/unitree_g1/g1_29dof.urdf");
  const std::vector<FootPoints> feet = FeetOnModel(LoadRobotMap(root + "/manifests/robots/g1.toml"), model);
  std::vector<double> time, q, u;
  const int frames = 1201;  // 10 s at 120 Hz -> 10,001 evaluation frames at 1 kHz
  for (int t = 0; t < frames; ++t) {
    time.push_back(t / 120.0);
    Eigen::VectorXd qt = model.defaultQ();
    qt[6] = 0.75;
    for (int i = 7; i < model.nq(); ++i) qt[i] = 0.3 * std::sin(0.05 * t + i);
    q.insert(q.end(), qt.data(), qt.data() + qt.size());
    for (int i = 0; i < model.nu(); ++i) u.push_back(i < 6 ? 0.0 : 0.3 * 0.05 * 120 * std::cos(0.05 * t + i + 1));
  }
  MotionEvaluator evaluator(model, feet, 1000.0, {});
  int64_t processed = 0;
  for (auto _ : state) {
    RangeMetrics whole;
    (void)evaluator.evaluate(time, q, u, {}, 0.0, &whole, all_metrics);
    benchmark::DoNotOptimize(whole.mean_delta_p);
    processed += whole.eval_frames;
  }
  state.counters["frames_per_second"] = benchmark::Counter(static_cast<double>(processed), benchmark::Counter::kIsRate);
}

void EvaluateStageG1(benchmark::State& state) {
  const std::string root = SYN_SOURCE_DIR;
  const Model model = Model::Load(root + "/datasets/robots/unitree_g1/g1_29dof.urdf");
  const std::vector<FootPoints> feet = FeetOnModel(LoadRobotMap(root + "/manifests/robots/g1.toml"), model);
  MotionData motion;
  motion.coordinate_names = model.coordinateNames();
  motion.velocity_names = model.velocityNames();
  motion.model_sha256 = model.sourceSha256();
  const int frames = 481;  // 4 s at 120 Hz
  for (int t = 0; t < frames; ++t) {
    motion.time_s.push_back(t / 120.0);
    Eigen::VectorXd qt = model.defaultQ();
    qt[6] = 0.75;
    for (int i = 7; i < model.nq(); ++i) qt[i] = 0.3 * std::sin(0.05 * t + i);
    motion.q.insert(motion.q.end(), qt.data(), qt.data() + qt.size());
    for (int i = 0; i < model.nu(); ++i) motion.u.push_back(i < 6 ? 0.0 : 0.3 * 0.05 * 120 * std::cos(0.05 * t + i + 1));
  }
  const std::vector<int64_t> boundaries = {0, 120, 240, 360, frames};  // four 1 s segments
  const TrialSynergies synergies = ComputeTrialSynergies(motion, boundaries, {});
  const EvaluateOptions options;  // 1 kHz, 100 samples
  const int64_t eval_frames = 4001;  // 4 s at 1 kHz
  int64_t processed = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(EvaluateMotion(motion, model, feet, &synergies, options, "bench.synergies.h5").size());
    processed += eval_frames * (1 + options.monte_carlo.samples);
  }
  state.counters["frames_per_second"] = benchmark::Counter(static_cast<double>(processed), benchmark::Counter::kIsRate);
}

BENCHMARK(EvaluateG1)->Arg(1)->ArgName("all_metrics")->Unit(benchmark::kMillisecond);
BENCHMARK(EvaluateG1)->Arg(0)->ArgName("all_metrics")->Unit(benchmark::kMillisecond);
BENCHMARK(EvaluateStageG1)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace syn

BENCHMARK_MAIN();
