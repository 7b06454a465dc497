// syn-evaluate throughput on G1 at the paper's 1 kHz: per evaluation frame a
// cubic resample of q and u, Simbody's A·u, and (for every metric) inverse
// dynamics and the foot sole points; the Monte-Carlo samples need A·u only.
// EvaluateStageG1 runs the stage's default workload (the trial with every
// metric, then 100 Monte-Carlo reconstructions of each segment) and counts
// every evaluated frame. EvaluateCmuWalk is the issue-19 target: a real
// 8.3 s CMU walk (the first 996 frames of ../shared/datasets/cmu_bvh 09_12,
// ingested, retargeted, segmented and decomposed as the pipeline does) at the
// paper's protocol — 1 kHz, 100 reconstructions per segment — per thread
// count, in wall time.
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <optional>

#include "common/model.h"
#include "stages/evaluate/evaluate.h"
#include "stages/evaluate/motion_metrics.h"
#include "stages/ingest/ingest.h"
#include "stages/retarget/retarget.h"
#include "common/markers_file.h"
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

// The walk, its synergies and the grid points one evaluation visits; computed once.
struct CmuWalk {
  MotionData motion;
  TrialSynergies synergies;
  int64_t grid_points = 0;  // trial + per segment (original + rank k + 100 samples) × its grid frames
};

const CmuWalk* LoadCmuWalk(const Model& model, const std::vector<FootPoints>& feet) {
  static std::optional<CmuWalk> walk;
  if (walk) return &*walk;
  const std::string bvh = std::string(SYN_SHARED_DATASETS) + "/cmu_bvh/09/09_12.bvh";
  if (!std::filesystem::exists(bvh)) return nullptr;
  const std::string root = SYN_SOURCE_DIR;
  IngestOptions ingest;
  ingest.drop_first_frame = true;  // cgspeed's T-pose frame (manifests/cmu15.toml)
  MarkerData capture = IngestCapture(bvh, ingest, nullptr);
  const std::string markers =
      std::filesystem::temp_directory_path() / ("syn_bench_walk_" + std::to_string(::getpid()) + ".markers.h5");
  {
    IntermediateWriter writer(markers, {kMarkersSchema, kMarkersSchemaVersion, "bench", {}, nlohmann::json::array()});
    WriteMarkerData(writer, capture);
    writer.commit();
  }
  RetargetOptions retarget;
  retarget.model = root + "/datasets/robots/unitree_g1/g1_29dof.urdf";
  retarget.robot_map = root + "/manifests/robots/g1.toml";
  retarget.markerset = root + "/manifests/markersets/cmu-bvh.toml";
  MotionData motion = RetargetFile(markers, retarget, nullptr);
  std::filesystem::remove(markers);
  // The first 996 frames: 8.29 s of forward walking.
  const size_t frames = 996, nq = static_cast<size_t>(motion.nq()), nu = static_cast<size_t>(motion.nu());
  motion.time_s.resize(frames);
  motion.q.resize(frames * nq);
  motion.u.resize(frames * nu);
  motion.udot.resize(frames * nu);
  motion.tau.resize(frames * nu);
  motion.landmark_targets.resize(frames * motion.landmark_names.size() * 7);
  motion.landmark_error.resize(frames * motion.landmark_names.size() * 2);
  walk.emplace();
  walk->synergies = ComputeTrialSynergies(motion, SegmentMotion(motion, model, {}).boundaries, {});
  const EvaluateOptions options;
  const nlohmann::json metrics = EvaluateMotion(motion, model, feet, &walk->synergies, options, "bench");
  walk->grid_points = metrics["trial"]["eval_frames"].get<int64_t>();
  for (const nlohmann::json& segment : metrics["segments"]) {
    walk->grid_points += (2 + options.monte_carlo.samples) * segment["monte_carlo"]["original"]["eval_frames"].get<int64_t>();
  }
  walk->motion = std::move(motion);
  return &*walk;
}

void EvaluateCmuWalk(benchmark::State& state) {
  const std::string root = SYN_SOURCE_DIR;
  const Model model = Model::Load(root + "/datasets/robots/unitree_g1/g1_29dof.urdf");
  const std::vector<FootPoints> feet = FeetOnModel(LoadRobotMap(root + "/manifests/robots/g1.toml"), model);
  const CmuWalk* walk = LoadCmuWalk(model, feet);
  if (!walk) {
    state.SkipWithError("shared dataset absent: ../shared/datasets/cmu_bvh/09/09_12.bvh");
    return;
  }
  EvaluateOptions options;  // the paper's protocol: 1 kHz, 100 samples, seed 1
  options.threads = static_cast<int>(state.range(0));
  options.momentum = state.range(1) ? MomentumOperator::kTree : MomentumOperator::kSimbody;
  for (auto _ : state) {
    benchmark::DoNotOptimize(EvaluateMotion(walk->motion, model, feet, &walk->synergies, options, "bench").size());
  }
  const double duration = walk->motion.time_s.back() - walk->motion.time_s.front();
  state.counters["grid_frames_per_second"] =
      benchmark::Counter(static_cast<double>(walk->grid_points) * static_cast<double>(state.iterations()),
                         benchmark::Counter::kIsRate);
  state.counters["motion_s_per_s"] =
      benchmark::Counter(duration * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
}

BENCHMARK(EvaluateCmuWalk)
    ->ArgsProduct({{1, 2}, {1}})
    ->Args({1, 0})
    ->ArgNames({"threads", "tree"})
    ->UseRealTime()
    ->Unit(benchmark::kMillisecond);
BENCHMARK(EvaluateG1)->Arg(1)->ArgName("all_metrics")->Unit(benchmark::kMillisecond);
BENCHMARK(EvaluateG1)->Arg(0)->ArgName("all_metrics")->Unit(benchmark::kMillisecond);
BENCHMARK(EvaluateStageG1)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace syn

BENCHMARK_MAIN();
