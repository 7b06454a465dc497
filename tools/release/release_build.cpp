#include "tools/release/release_build.h"

#include <array>
#include <cstdio>
#include <memory>
#include <sstream>

#include <nlohmann/json.hpp>

#include "common/version.h"

namespace syn {

std::string DependencyVersionsJson() {
  const char* command =
      "dpkg-query -W -f='${Package} ${Version}\\n' libsimbody-dev libceres-dev libeigen3-dev libhdf5-dev "
      "libsuitesparse-dev g++ 2>/dev/null";
  nlohmann::json versions = nlohmann::json::object();
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command, "r"), pclose);
  if (!pipe) return versions.dump();
  std::string output;
  std::array<char, 4096> buffer;
  size_t read = 0;
  while ((read = fread(buffer.data(), 1, buffer.size(), pipe.get())) > 0) output.append(buffer.data(), read);
  std::istringstream lines(output);
  for (std::string package, version; lines >> package >> version;) versions[package] = version;
  return versions.dump();
}

std::string ProvenanceJson(const std::string& dataset_root) {
  nlohmann::json provenance;
  provenance["tool"] = std::string("synsculpt ") + kVersion;
  provenance["dataset_root"] = dataset_root;
  provenance["dependencies"] = nlohmann::json::parse(DependencyVersionsJson());
  return provenance.dump(2) + "\n";  // nlohmann objects are sorted: stable bytes
}

ReleaseSizes BuildRelease(const ReleaseManifest& manifest, const std::string& outputs_root, const std::string& dataset_root,
                          const std::string& tar_path) {
  std::vector<ReleaseFile> files = CollectPipelineFiles(manifest, outputs_root + "/" + manifest.name, ProvenanceJson(dataset_root));
  AddDerivedFiles(manifest, files);
  AddChecksums(files);
  return WriteReleaseTar(manifest, files, tar_path);
}

}  // namespace syn
