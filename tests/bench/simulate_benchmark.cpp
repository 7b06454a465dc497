// syn-simulate's speed: simulated seconds per wall-clock second on G1 at the paper's 1 kHz, per contact
// mode and integrator. The motions are smooth synthetic ones, so the benchmark needs no capture: in the
// paper's mode every joint a sinusoid with the pelvis held up (the controller's cost does not depend on
// what it tracks), on the ground the robot standing and swinging its arms (a motion it can balance).
#include <benchmark/benchmark.h>

#include <cmath>

#include "common/model.h"
#include "common/robot_map.h"
#include "stages/simulate/simulation.h"
#include "tests/support/synthetic_motions.h"

namespace syn {
namespace {

void SimulateG1(benchmark::State& state, ContactMode contact, Integrator integrator) {
  const Model model = Model::Load(std::string(SYN_SOURCE_DIR) + "/datasets/robots/unitree_g1/g1_29dof.urdf");
  const RobotMap map = LoadRobotMap(std::string(SYN_SOURCE_DIR) + "/manifests/robots/g1.toml");
  const double seconds = 1.0;
  const MotionData motion = contact == ContactMode::kGround ? testing::StandingMotion(model, map, seconds, 0.4)
                                                            : testing::SwayingMotion(model, seconds);
  SimulateOptions options;
  options.contact = contact;
  options.integrator = integrator;
  double simulated = 0;
  for (auto _ : state) {
    const SimulationResult result = Simulate(motion, "sway", model, map, options);
    benchmark::DoNotOptimize(result.motion.q.data());
    simulated += motion.time_s.back() - motion.time_s.front();
  }
  state.counters["simulated_s_per_s"] = benchmark::Counter(simulated, benchmark::Counter::kIsRate);
}

BENCHMARK_CAPTURE(SimulateG1, contact_none_euler, ContactMode::kNone, Integrator::kSemiImplicitEuler)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(SimulateG1, contact_none_rk4, ContactMode::kNone, Integrator::kRungeKutta4)
    ->Unit(benchmark::kMillisecond);
BENCHMARK_CAPTURE(SimulateG1, contact_ground_euler, ContactMode::kGround, Integrator::kSemiImplicitEuler)
    ->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace syn

BENCHMARK_MAIN();
