// Per-call cost of the model operators every stage's hot loop uses, for the
// default robot (G1) and the paper's robot (HRP-4C).
#include <benchmark/benchmark.h>

#include <filesystem>
#include <random>

#include "common/model.h"

namespace syn {
namespace {

struct Robot {
  const char* label;
  std::string path;
};

const Robot kRobots[] = {
    {"G1", std::string(SYN_SOURCE_DIR) + "/datasets/robots/unitree_g1/g1_29dof.urdf"},
    {"HRP4C", std::string(SYN_SHARED_DATASETS) + "/robots/humanoid_synergies/HRP4c_optitrack_model.urdf"},
};

struct Fixture {
  Model model;
  Workspace workspace;
  Eigen::VectorXd q, u, v, out;
  explicit Fixture(const std::string& path) : model(Model::Load(path)), workspace(model) {
    std::mt19937 random(1);
    std::uniform_real_distribution<double> uniform(-0.3, 0.3);
    q = model.defaultQ();
    for (int i = model.hasFreeBase() ? 7 : 0; i < model.nq(); ++i) q[i] = uniform(random);
    u = Eigen::VectorXd::NullaryExpr(model.nu(), [&] { return uniform(random); });
    v = Eigen::VectorXd::NullaryExpr(model.nu(), [&] { return uniform(random); });
    out.resize(model.nu());
    workspace.setQ(q);
    workspace.setU(u);
  }
};

void RealizePosition(benchmark::State& state, const Robot& robot) {
  Fixture f(robot.path);
  const int hand = f.model.findLinkIndex(f.model.linkNames().back());
  for (auto _ : state) {
    f.q[f.q.size() - 1] += 1e-9;
    f.workspace.setQ(f.q);
    benchmark::DoNotOptimize(f.workspace.findLinkPose(hand));
  }
  state.SetItemsProcessed(state.iterations());
}

void MassTimes(benchmark::State& state, const Robot& robot) {
  Fixture f(robot.path);
  for (auto _ : state) {
    f.workspace.calcMassTimes(f.v, f.out);
    benchmark::DoNotOptimize(f.out.data());
  }
  state.SetItemsProcessed(state.iterations());
}

void KineticEnergy(benchmark::State& state, const Robot& robot) {
  Fixture f(robot.path);
  for (auto _ : state) benchmark::DoNotOptimize(f.workspace.calcKineticEnergy());
  state.SetItemsProcessed(state.iterations());
}

void InverseDynamics(benchmark::State& state, const Robot& robot) {
  Fixture f(robot.path);
  for (auto _ : state) {
    f.workspace.calcInverseDynamics(f.v, f.out);
    benchmark::DoNotOptimize(f.out.data());
  }
  state.SetItemsProcessed(state.iterations());
}

void FrameJacobian(benchmark::State& state, const Robot& robot) {
  Fixture f(robot.path);
  Eigen::Matrix<double, 6, Eigen::Dynamic> jacobian(6, f.model.nu());
  const int link = f.model.findLinkIndex(f.model.linkNames().back());
  for (auto _ : state) {
    f.workspace.calcFrameJacobian(link, Eigen::Vector3d(0.01, 0, 0), jacobian);
    benchmark::DoNotOptimize(jacobian.data());
  }
  state.SetItemsProcessed(state.iterations());
}

void Register() {
  for (const Robot& robot : kRobots) {
    if (!std::filesystem::exists(robot.path)) continue;
    const std::string name(robot.label);
    benchmark::RegisterBenchmark(("Model/" + name + "/RealizePosition").c_str(), RealizePosition, robot);
    benchmark::RegisterBenchmark(("Model/" + name + "/MassTimesVector").c_str(), MassTimes, robot);
    benchmark::RegisterBenchmark(("Model/" + name + "/KineticEnergy").c_str(), KineticEnergy, robot);
    benchmark::RegisterBenchmark(("Model/" + name + "/InverseDynamics").c_str(), InverseDynamics, robot);
    benchmark::RegisterBenchmark(("Model/" + name + "/FrameJacobian").c_str(), FrameJacobian, robot);
  }
}

}  // namespace
}  // namespace syn

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  syn::Register();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
