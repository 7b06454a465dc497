// Read throughput of each capture format, parsing from memory (the file is
// read once before timing), in point samples per second (frames × points, or
// frames × bodies for BVH and HumanML3D).
#include <benchmark/benchmark.h>

#include <filesystem>
#include <string>

#include "common/file_bytes.h"
#include "stages/ingest/bvh_reader.h"
#include "stages/ingest/c3d_reader.h"
#include "stages/ingest/motive_csv_reader.h"
#include "stages/ingest/trc_reader.h"

namespace syn {
namespace {

std::string Shared(const std::string& relative) { return std::string(SYN_SHARED_DATASETS) + "/" + relative; }

void CountSamples(benchmark::State& state, const MarkerData& data) {
  const double samples = static_cast<double>(data.frame_count()) *
                         static_cast<double>(data.labels.size() + data.computed_labels.size() + data.bodies.size());
  state.counters["samples_per_second"] = benchmark::Counter(samples * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["frames"] = static_cast<double>(data.frame_count());
}

void C3d(benchmark::State& state, const std::string& relative) {
  const std::vector<uint8_t> bytes = ReadFileBytes(Shared(relative));
  MarkerData data;
  for (auto _ : state) {
    data = ParseC3d(bytes.data(), bytes.size(), relative);
    benchmark::DoNotOptimize(data.points.data());
  }
  CountSamples(state, data);
}

void Bvh(benchmark::State& state, const std::string& relative) {
  const std::string text = ReadFileText(Shared(relative));
  MarkerData data;
  for (auto _ : state) {
    data = ParseBvh(text, relative, {});
    benchmark::DoNotOptimize(data.body_pose.data());
  }
  CountSamples(state, data);
}

void Trc(benchmark::State& state, const std::string& relative) {
  const std::string text = ReadFileText(Shared(relative));
  MarkerData data;
  for (auto _ : state) {
    data = ParseTrc(text, relative);
    benchmark::DoNotOptimize(data.points.data());
  }
  CountSamples(state, data);
}

void Motive(benchmark::State& state, const std::string& relative) {
  const std::string text = ReadFileText(Shared(relative));
  MarkerData data;
  for (auto _ : state) {
    data = ParseMotiveCsv(text, relative);
    benchmark::DoNotOptimize(data.points.data());
  }
  CountSamples(state, data);
}

void Register() {
  const auto add = [](const char* name, void (*function)(benchmark::State&, const std::string&), const std::string& file) {
    if (std::filesystem::exists(Shared(file))) benchmark::RegisterBenchmark(name, function, file)->Unit(benchmark::kMillisecond);
  };
  add("Read/C3D/float/HDM05_5920x44", C3d, "c3d/hdm05/HDM_bd_05-01_01_120.c3d");
  add("Read/C3D/float/CMU_85_12_4499x41", C3d, "c3d/cmu/85_12.c3d");
  add("Read/C3D/int16/sub_labels_333x114", C3d, "c3d/c3d_org/sample04/sub_labels.c3d");
  add("Read/BVH/CMU_03_04", Bvh, "cmu_bvh/03/03_04.bvh");
  add("Read/TRC/squats1", Trc, "trc/addbiomechanics_expert1/squats1.trc");
  add("Read/MotiveCSV/markers", Motive, "motive_csv/test_markers_enabled.csv");
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
