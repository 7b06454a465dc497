// syn-studio's budget: one slider move = POST /api/compose of the whole script = compose + metrics + JSON,
// which must stay under 50 ms for a 4 s motion to follow the slider. StudioCompose4s times
// Studio::compose (everything the server does but the socket) on a 4 s script of the demo library
// (outputs/demo/library.h5, `make demo`): two steps of two repetitions of 1 s, keyframed gains. The parts
// are timed too: Composer::compose alone (limits, integration, inverse dynamics) and the metrics (1 kHz).
#include <benchmark/benchmark.h>

#include <filesystem>

#include "common/library_file.h"
#include "common/model.h"
#include "common/robot_map.h"
#include "stages/compose/compose_script.h"
#include "stages/compose/composer.h"
#include "stages/evaluate/evaluate.h"
#include "tools/studio/studio.h"

namespace syn {
namespace {

const std::string kRoot = SYN_SOURCE_DIR;
const std::string kLibrary = kRoot + "/outputs/demo/library.h5";
const std::string kModel = kRoot + "/datasets/robots/unitree_g1/g1_29dof.urdf";
const std::string kMap = kRoot + "/manifests/robots/g1.toml";

std::string Script() {
  return "model = \"" + kModel + "\"\n"
         "[[step]]\nsynergy = \"salsa/60_10/1\"\nduration = 1.0\nrepetitions = 2\n"
         "[[step.keyframe]]\nat = 0.0\ngain = [0.8, 1.0, 1.0]\n[[step.keyframe]]\nat = 1.0\ngain = [1.2, 1.0, 1.0]\n"
         "[[step]]\nsynergy = \"modern/05_02/1\"\nduration = 1.0\nrepetitions = 2\ninterpolation = \"cubic\"\n"
         "gain = [1.1, 0.9, 1.0]\n";
}

bool HaveLibrary(benchmark::State& state) {
  if (std::filesystem::exists(kLibrary)) return true;
  state.SkipWithError(("no demo library at " + kLibrary + " (make demo)").c_str());
  return false;
}

void StudioCompose4s(benchmark::State& state) {
  if (!HaveLibrary(state)) return;
  const Studio studio(kLibrary, kModel, kMap, StudioOptions{});
  const std::string script = Script();
  double seconds = 0;
  for (auto _ : state) {
    const nlohmann::json result = studio.compose(script, "bench.toml");
    seconds = result["time"].back().get<double>();
    benchmark::DoNotOptimize(result.size());
  }
  state.counters["motion_s"] = seconds;
}

void ComposerOnly4s(benchmark::State& state) {
  if (!HaveLibrary(state)) return;
  const Model model = Model::Load(kModel);
  const LibraryReader library(kLibrary);
  const ComposeScript script = ParseComposeScript(Script(), "bench.toml");
  const Composer composer(script, library, model, Composer::StartPose(script, library));
  for (auto _ : state) {
    const ComposedMotion composed = composer.compose();
    benchmark::DoNotOptimize(composed.motion.q.data());
  }
}

void Metrics4s(benchmark::State& state) {
  if (!HaveLibrary(state)) return;
  const Model model = Model::Load(kModel);
  const LibraryReader library(kLibrary);
  const ComposeScript script = ParseComposeScript(Script(), "bench.toml");
  const ComposedMotion composed = Composer(script, library, model, Composer::StartPose(script, library)).compose();
  MotionEvaluator evaluator(model, FeetOnModel(LoadRobotMap(kMap), model), StudioOptions{}.eval_rate, {});
  const MotionData& motion = composed.motion;
  for (auto _ : state) {
    RangeMetrics whole;
    (void)evaluator.evaluate(motion.time_s, motion.q, motion.u, {}, 0.0, &whole);
    benchmark::DoNotOptimize(whole.mean_delta_p);
  }
}

BENCHMARK(StudioCompose4s)->Unit(benchmark::kMillisecond);
BENCHMARK(ComposerOnly4s)->Unit(benchmark::kMillisecond);
BENCHMARK(Metrics4s)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace syn

BENCHMARK_MAIN();
