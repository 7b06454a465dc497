// syn-simulate's speed: simulated seconds per wall-clock second on G1 at the paper's 1 kHz, per contact
// mode and integrator. The motion is a smooth synthetic one (every joint a sinusoid, the pelvis still),
// so the benchmark needs no capture; the controller's cost does not depend on what it tracks.
#include <benchmark/benchmark.h>

#include <cmath>

#include "common/model.h"
#include "common/robot_map.h"
#include "stages/simulate/simulation.h"

namespace syn {
namespace {

MotionData SwayingMotion(const Model& model, double seconds) {
  MotionData motion;
  motion.coordinate_names = model.coordinateNames();
  motion.velocity_names = model.velocityNames();
  motion.model_name = model.name();
  motion.model_sha256 = model.sourceSha256();
  const int frames = static_cast<int>(seconds * 120.0) + 1;
  for (int t = 0; t < frames; ++t) {
    const double time = t / 120.0;
    motion.time_s.push_back(time);
    Eigen::VectorXd q = model.defaultQ(), u = Eigen::VectorXd::Zero(model.nu()), udot = u;
    q[6] = 0.75;  // pelvis height, m
    for (int i = 7; i < model.nq(); ++i) {
      const double w = 2.0 + 0.1 * i;  // rad/s
      q[i] = 0.2 * std::sin(w * time + i);
      u[i - 1] = 0.2 * w * std::cos(w * time + i);
      udot[i - 1] = -0.2 * w * w * std::sin(w * time + i);
    }
    motion.q.insert(motion.q.end(), q.data(), q.data() + q.size());
    motion.u.insert(motion.u.end(), u.data(), u.data() + u.size());
    motion.udot.insert(motion.udot.end(), udot.data(), udot.data() + udot.size());
    motion.tau.insert(motion.tau.end(), static_cast<size_t>(model.nu()), 0.0);
  }
  return motion;
}

void SimulateG1(benchmark::State& state, ContactMode contact, Integrator integrator) {
  const Model model = Model::Load(std::string(SYN_SOURCE_DIR) + "/datasets/robots/unitree_g1/g1_29dof.urdf");
  const RobotMap map = LoadRobotMap(std::string(SYN_SOURCE_DIR) + "/manifests/robots/g1.toml");
  const double seconds = 1.0;
  const MotionData motion = SwayingMotion(model, seconds);
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

}  // namespace
}  // namespace syn

BENCHMARK_MAIN();
