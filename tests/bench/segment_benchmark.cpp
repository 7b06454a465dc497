// Segmentation throughput on G1: momentum A(q)u per frame (Simbody's O(n)
// product after realising positions), resampling and thresholding.
#include <benchmark/benchmark.h>

#include <cmath>

#include "common/model.h"
#include "stages/segment/segmentation.h"

namespace syn {
namespace {

void SegmentG1(benchmark::State& state) {
  const Model model = Model::Load(std::string(SYN_SOURCE_DIR) + "/datasets/robots/unitree_g1/g1_29dof.urdf");
  MotionData motion;
  motion.coordinate_names = model.coordinateNames();
  motion.velocity_names = model.velocityNames();
  motion.model_sha256 = model.sourceSha256();
  const int frames = 1200;  // 10 s at 120 Hz
  for (int t = 0; t < frames; ++t) {
    motion.time_s.push_back(t / 120.0);
    Eigen::VectorXd q = model.defaultQ();
    for (int i = 7; i < model.nq(); ++i) q[i] = 0.3 * std::sin(0.05 * t + i);
    motion.q.insert(motion.q.end(), q.data(), q.data() + q.size());
    for (int i = 0; i < model.nu(); ++i) motion.u.push_back(std::cos(0.05 * t + i));
  }
  int64_t processed = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(SegmentMotion(motion, model, {}).boundaries.data());
    processed += frames;
  }
  state.counters["frames_per_second"] = benchmark::Counter(static_cast<double>(processed), benchmark::Counter::kIsRate);
}

BENCHMARK(SegmentG1)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace syn

BENCHMARK_MAIN();
