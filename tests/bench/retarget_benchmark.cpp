// Retargeting throughput on G1: per-frame IK on exact targets from a smooth
// trajectory (frames per second, warm-started as in syn-retarget), and
// inverse dynamics per frame (setQ + setU + ID).
#include <benchmark/benchmark.h>

#include <cmath>

#include "common/model.h"
#include "stages/retarget/frame_ik.h"
#include "stages/retarget/robot_map.h"

namespace syn {
namespace {

struct G1Targets {
  Model model = Model::Load(std::string(SYN_SOURCE_DIR) + "/datasets/robots/unitree_g1/g1_29dof.urdf");
  RobotMap map = LoadRobotMap(std::string(SYN_SOURCE_DIR) + "/manifests/robots/g1.toml");
  std::vector<IkTask> tasks;
  std::vector<Eigen::VectorXd> trajectory;
  std::vector<std::vector<IkTarget>> targets;

  G1Targets() {
    Workspace workspace(model);
    for (const RobotTask& task : map.tasks) {
      tasks.push_back({model.findLinkIndex(task.link), task.type, map.priority_weights[static_cast<size_t>(task.priority - 1)]});
    }
    for (int t = 0; t < 240; ++t) {
      Eigen::VectorXd q = model.defaultQ();
      q[6] = 0.75;
      for (int i = 7; i < model.nq(); ++i) {
        const double amplitude = 0.2 * std::min(model.qUpper()[i], -model.qLower()[i]);
        q[i] = amplitude * std::sin(2 * M_PI * 0.5 * t / 120.0 + i);
      }
      workspace.setQ(q);
      std::vector<IkTarget> frame;
      for (const IkTask& task : tasks) {
        const Eigen::Isometry3d pose = workspace.findLinkPose(task.link);
        frame.push_back({true, true, pose.translation(), Eigen::Quaterniond(pose.linear())});
      }
      trajectory.push_back(q);
      targets.push_back(frame);
    }
  }
};

void FrameIkG1(benchmark::State& state) {
  G1Targets g1;
  const double posture = g1.map.priority_weights[2] * g1.map.posture_weight;
  FrameIk ik(g1.model, g1.tasks, g1.model.defaultQ(), posture);
  int64_t frames = 0, iterations = 0;
  for (auto _ : state) {
    Eigen::VectorXd q = g1.trajectory[0];
    for (const auto& frame : g1.targets) iterations += ik.solve(frame, q).iterations;
    frames += static_cast<int64_t>(g1.targets.size());
  }
  state.counters["frames_per_second"] = benchmark::Counter(static_cast<double>(frames), benchmark::Counter::kIsRate);
  state.counters["iterations_per_frame"] = static_cast<double>(iterations) / static_cast<double>(frames);
}

void InverseDynamicsG1(benchmark::State& state) {
  G1Targets g1;
  Workspace workspace(g1.model);
  Eigen::VectorXd u = Eigen::VectorXd::Constant(g1.model.nu(), 0.1), udot = Eigen::VectorXd::Constant(g1.model.nu(), 0.5), tau;
  int64_t frames = 0;
  for (auto _ : state) {
    for (const Eigen::VectorXd& q : g1.trajectory) {
      workspace.setQ(q);
      workspace.setU(u);
      workspace.calcInverseDynamics(udot, tau);
      benchmark::DoNotOptimize(tau.data());
    }
    frames += static_cast<int64_t>(g1.trajectory.size());
  }
  state.counters["frames_per_second"] = benchmark::Counter(static_cast<double>(frames), benchmark::Counter::kIsRate);
}

BENCHMARK(FrameIkG1)->Unit(benchmark::kMillisecond);
BENCHMARK(InverseDynamicsG1)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace syn

BENCHMARK_MAIN();
