// Retargeting throughput on G1: per-frame IK on exact targets from a smooth
// trajectory (frames per second, warm-started as in syn-retarget) against
// Simbody's Assembler (Markers + OrientationSensors goals, the engine behind
// OpenSim IK) on the same targets, each with its tracking error; and inverse
// dynamics per frame (setQ + setU + ID).
#include <benchmark/benchmark.h>

#include <cmath>
#include <filesystem>
#include <string>

#include <unistd.h>

#include "common/assembler_tracking.h"
#include "common/model.h"
#include "stages/retarget/frame_ik.h"
#include "common/robot_map.h"
#include "stages/retarget/retarget.h"
#include "stages/retarget/trajectory_refinement.h"
#include "common/intermediate_file.h"
#include "common/markers_file.h"
#include "stages/ingest/ingest.h"

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

// RMS link position (mm) and orientation (deg) error of a solved frame against its targets.
struct TrackingError {
  double position_sq = 0, angle_sq = 0;
  int64_t positions = 0, angles = 0;
  void add(Workspace& workspace, const std::vector<IkTask>& tasks, const std::vector<IkTarget>& targets, const Eigen::VectorXd& q) {
    workspace.setQ(q);
    for (size_t i = 0; i < tasks.size(); ++i) {
      const Eigen::Isometry3d pose = workspace.findLinkPose(tasks[i].link);
      if (tasks[i].type != TaskType::kOrientation) {
        position_sq += (pose.translation() - targets[i].position).squaredNorm(), ++positions;
      }
      if (tasks[i].type != TaskType::kPosition) {
        const double angle = Eigen::AngleAxisd(pose.linear() * targets[i].orientation.toRotationMatrix().transpose()).angle();
        angle_sq += angle * angle, ++angles;
      }
    }
  }
  void report(benchmark::State& state) const {
    state.counters["position_rms_mm"] = 1000 * std::sqrt(position_sq / static_cast<double>(std::max<int64_t>(1, positions)));
    state.counters["angle_rms_deg"] = 180 / M_PI * std::sqrt(angle_sq / static_cast<double>(std::max<int64_t>(1, angles)));
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
  Workspace workspace(g1.model);
  TrackingError error;
  Eigen::VectorXd q = g1.trajectory[0];
  ik.forgetHistory();
  for (const auto& frame : g1.targets) {
    ik.solve(frame, q);
    error.add(workspace, g1.tasks, frame, q);
  }
  error.report(state);
}

void AssemblerG1(benchmark::State& state) {
  G1Targets g1;
  std::vector<AssemblerTask> tasks;
  for (const IkTask& task : g1.tasks) {
    tasks.push_back({task.link, task.type != TaskType::kOrientation, task.type != TaskType::kPosition, task.weight});
  }
  std::vector<std::vector<Eigen::Vector3d>> positions;
  std::vector<std::vector<Eigen::Quaterniond>> orientations;
  for (const auto& frame : g1.targets) {
    positions.emplace_back();
    orientations.emplace_back();
    for (const IkTarget& target : frame) {
      positions.back().push_back(target.position);
      orientations.back().push_back(target.orientation);
    }
  }
  int64_t frames = 0;
  TrackingError error;
  Workspace workspace(g1.model);
  bool first_pass = true;
  for (auto _ : state) {
    AssemblerTracker assembler(g1.model, tasks);
    Eigen::VectorXd q = g1.trajectory[0];
    for (size_t t = 0; t < g1.targets.size(); ++t) {
      assembler.track(positions[t], orientations[t], q);
      if (first_pass) {
        state.PauseTiming();
        error.add(workspace, g1.tasks, g1.targets[t], q);
        state.ResumeTiming();
      }
    }
    first_pass = false;
    frames += static_cast<int64_t>(g1.targets.size());
  }
  state.counters["frames_per_second"] = benchmark::Counter(static_cast<double>(frames), benchmark::Counter::kIsRate);
  error.report(state);
}

// The trajectory refinement over the per-frame IK solutions of the same targets (windows of 60 frames
// overlapping by 15, as in syn-retarget): frames per second of the refinement alone.
void RefinementG1(benchmark::State& state) {
  G1Targets g1;
  const double posture = g1.map.priority_weights[2] * g1.map.posture_weight;
  FrameIk ik(g1.model, g1.tasks, g1.model.defaultQ(), posture);
  const int64_t nq = g1.model.nq();
  std::vector<double> times, solved;
  Eigen::VectorXd q = g1.trajectory[0];
  for (size_t t = 0; t < g1.targets.size(); ++t) {
    ik.solve(g1.targets[t], q);
    times.push_back(static_cast<double>(t) / 120.0);
    solved.insert(solved.end(), q.data(), q.data() + nq);
  }
  int64_t frames = 0;
  for (auto _ : state) {
    std::vector<double> refined = solved;
    RefineTrajectory(ik, g1.model, g1.targets, times, refined, {});
    benchmark::DoNotOptimize(refined.data());
    frames += static_cast<int64_t>(g1.targets.size());
  }
  state.counters["frames_per_second"] = benchmark::Counter(static_cast<double>(frames), benchmark::Counter::kIsRate);
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

// The whole stage on a real capture (the bundled CMU walk 02_01 onto G1): IK, refinement, contact
// enforcement (range(0) = 1) or not (0), inverse dynamics; frames of the capture per second.
void RetargetStageRealWalkG1(benchmark::State& state) {
  const std::string source = std::string(SYN_SOURCE_DIR);
  const std::string markers = std::filesystem::temp_directory_path() / ("syn_bench_retarget_" + std::to_string(::getpid()) + ".markers.h5");
  IngestOptions ingest;
  ingest.drop_first_frame = true;
  {
    IntermediateWriter writer(markers, {kMarkersSchema, kMarkersSchemaVersion, "bench", {}, nlohmann::json::array()});
    WriteMarkerData(writer, IngestCapture(source + "/datasets/demo/02_01.bvh", ingest, nullptr));
    writer.commit();
  }
  RetargetOptions options;
  options.model = source + "/datasets/robots/unitree_g1/g1_29dof.urdf";
  options.robot_map = source + "/manifests/robots/g1.toml";
  options.markerset = source + "/manifests/markersets/cmu-bvh.toml";
  options.enforce_contacts = state.range(0) != 0;
  const RetargetInputs inputs = LoadRetargetInputs(markers, options);
  Workspace workspace(inputs.model);
  int64_t frames = 0;
  for (auto _ : state) {
    const MotionData motion = Retarget(inputs, workspace, options, nullptr);
    benchmark::DoNotOptimize(motion.q.data());
    frames += motion.frames();
  }
  std::filesystem::remove(markers);
  state.counters["frames_per_second"] = benchmark::Counter(static_cast<double>(frames), benchmark::Counter::kIsRate);
}

BENCHMARK(RetargetStageRealWalkG1)->Arg(0)->Arg(1)->Unit(benchmark::kMillisecond);
BENCHMARK(FrameIkG1)->Unit(benchmark::kMillisecond);
BENCHMARK(AssemblerG1)->Unit(benchmark::kMillisecond);
BENCHMARK(RefinementG1)->Unit(benchmark::kMillisecond);
BENCHMARK(InverseDynamicsG1)->Unit(benchmark::kMillisecond);

}  // namespace
}  // namespace syn

BENCHMARK_MAIN();
