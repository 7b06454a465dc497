#include "tests/support/demo_motion.h"

#include <unistd.h>

#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <iterator>
#include <map>
#include <memory>
#include <sstream>
#include <stdexcept>

#include "common/markers_file.h"
#include "stages/ingest/ingest.h"
#include "stages/retarget/retarget.h"
#include "tests/support/shared_data.h"

namespace syn::testing {

namespace {

// The stage's computation, ingest then retarget, with the pipeline's options for CMU BVH.
MotionData RetargetCmuBvhOnG1(const std::string& bvh_path) {
  const std::string dir = std::filesystem::temp_directory_path() / ("syn_demo_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  IngestOptions ingest;
  ingest.drop_first_frame = true;  // CMU's first frame is the T-pose (manifests/demo.toml)
  const MarkerData capture = IngestCapture(bvh_path, ingest, nullptr);
  const std::string markers = dir + "/capture.markers.h5";
  {
    IntermediateWriter writer(markers, {kMarkersSchema, kMarkersSchemaVersion, "test", {}, nlohmann::json::array()});
    WriteMarkerData(writer, capture);
    writer.commit();
  }
  RetargetOptions retarget;
  retarget.model = SourcePath(kG1Urdf);
  retarget.robot_map = SourcePath(kG1Map);
  retarget.markerset = SourcePath(kCmuMarkerset);
  MotionData motion = RetargetFile(markers, retarget, nullptr);
  std::filesystem::remove_all(dir);
  return motion;
}

std::string FileContents(const std::string& path) {
  std::ifstream file(path, std::ios::binary);
  if (!file) throw std::runtime_error("test cache: cannot read " + path);
  return std::string(std::istreambuf_iterator<char>(file), std::istreambuf_iterator<char>());
}

// Names the cached motion of `bvh_path`: the contents of every input the computation reads, and this test
// executable's own size and time (the ingest and retarget code is linked into it), so an edited robot map
// or a rebuilt retargeter misses.
std::filesystem::path CachePath(const std::string& bvh_path) {
  std::string material;
  for (const std::string& input : {bvh_path, SourcePath(kG1Urdf), SourcePath(kG1Map), SourcePath(kCmuMarkerset)}) {
    material += FileContents(input);
    material += '\0';
  }
  const std::filesystem::path executable = std::filesystem::read_symlink("/proc/self/exe");
  material += executable.string() + '\0' + std::to_string(std::filesystem::file_size(executable)) + '\0' +
              std::to_string(std::filesystem::last_write_time(executable).time_since_epoch().count());
  std::ostringstream name;
  name << std::filesystem::path(bvh_path).stem().string() << '-' << std::hex << std::hash<std::string>{}(material) << ".motion.h5";
  return std::filesystem::path(SYN_TEST_CACHE_DIR) / name.str();
}

// The fields `a` and `b` differ in, comma-separated ("" when none).
std::string MotionDifferences(const MotionData& a, const MotionData& b) {
  std::string differ;
  const auto check = [&](bool same, const char* field) {
    if (!same) differ += std::string(differ.empty() ? "" : ", ") + field;
  };
  check(SameBits(a.time_s, b.time_s), "time_s");
  check(a.coordinate_names == b.coordinate_names, "coordinate_names");
  check(a.velocity_names == b.velocity_names, "velocity_names");
  check(SameBits(a.q, b.q), "q");
  check(SameBits(a.u, b.u), "u");
  check(SameBits(a.udot, b.udot), "udot");
  check(SameBits(a.tau, b.tau), "tau");
  check(a.landmark_names == b.landmark_names, "landmark_names");
  check(SameBits(a.landmark_targets, b.landmark_targets), "landmark_targets");
  check(SameBits(a.landmark_error, b.landmark_error), "landmark_error");
  check(a.contact_feet == b.contact_feet, "contact_feet");
  check(a.contact == b.contact, "contact");
  check(SameBits(a.contact_force, b.contact_force), "contact_force");
  check(SameBits(a.unexplained_wrench, b.unexplained_wrench), "unexplained_wrench");
  check(a.model_name == b.model_name, "model_name");
  check(a.model_sha256 == b.model_sha256, "model_sha256");
  check(a.total_mass == b.total_mass, "total_mass");
  return differ;
}

}  // namespace

bool SameBits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && (a.empty() || std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0);
}

MotionData CmuBvhOnG1(const std::string& bvh_path) {
  const std::filesystem::path cached = CachePath(bvh_path);
  if (std::filesystem::exists(cached)) return ReadMotionFile(cached.string());
  MotionData motion = RetargetCmuBvhOnG1(bvh_path);
  // Written under this process's own name and renamed: tests run in parallel and may both miss.
  std::filesystem::create_directories(cached.parent_path());
  const std::string written = cached.string() + "." + std::to_string(::getpid());
  {
    IntermediateWriter writer(written, {kMotionSchema, kMotionSchemaVersion, "test cache", {}, nlohmann::json::array()});
    WriteMotionData(writer, motion);
    writer.commit();
  }
  // The cache is only good if the file gives back exactly what was computed.
  const std::string differences = MotionDifferences(ReadMotionFile(written), motion);
  if (!differences.empty()) {
    std::filesystem::remove(written);
    throw std::logic_error("test cache: " + written + " reads back with other " + differences + " than written");
  }
  std::filesystem::rename(written, cached);
  return motion;
}

const MotionData& DemoMotionOnG1(const std::string& trial) {
  static std::map<std::string, std::unique_ptr<MotionData>> cache;
  std::unique_ptr<MotionData>& motion = cache[trial];
  if (!motion) motion = std::make_unique<MotionData>(CmuBvhOnG1(SourcePath("datasets/demo/" + trial + ".bvh")));
  return *motion;
}

}  // namespace syn::testing
