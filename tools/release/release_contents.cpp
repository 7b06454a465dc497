#include "tools/release/release_contents.h"

#include <algorithm>
#include <filesystem>
#include <map>
#include <set>

#include "common/error.h"
#include "common/file_bytes.h"
#include "common/sha256.h"
#include "tools/release/datasheet.h"
#include "tools/release/tar_archive.h"
#include "tools/release/trial_quality.h"

namespace syn {
namespace fs = std::filesystem;

std::string ReleaseFile::contents() const { return disk_path.empty() ? bytes : ReadFileText(disk_path); }

std::string ReleaseFolderName(const ReleaseManifest& manifest) { return manifest.name + "-" + manifest.version; }

std::vector<ReleaseFile> CollectPipelineFiles(const ReleaseManifest& manifest, const std::string& output_dir,
                                              const std::string& provenance_json) {
  std::vector<ReleaseFile> files;
  const auto add = [&](const std::string& path, const std::string& disk_path) {
    if (!fs::is_regular_file(disk_path)) {
      throw DataError(Location::InFile(disk_path), "missing: the release needs it as " + path +
                                                       " (run `make run MANIFEST=" + manifest.path + "` first)");
    }
    files.push_back({path, disk_path, ""});
  };
  add("manifest.toml", manifest.path);
  files.push_back({"provenance.json", "", provenance_json});
  for (const std::string* robot_file : {&manifest.model, &manifest.robot_map, &manifest.model_licence_file}) {
    if (!robot_file->empty()) add("robot/" + fs::path(*robot_file).filename().string(), *robot_file);
  }
  add("library.h5", output_dir + "/library.h5");
  std::set<std::string> styles;
  for (const ReleaseTrial& trial : manifest.trials) styles.insert(trial.style);
  for (const std::string& style : styles) add("library/" + style + ".h5", output_dir + "/library/" + style + ".h5");
  for (const char* table : {"trials", "segments"}) add(std::string("summary/") + table + ".csv", output_dir + "/summary/" + table + ".csv");
  // Parameter stamps of this manifest's jobs only (a folder reused across manifest edits keeps old ones).
  std::set<std::string> stamp_owners = {"library", "summary"};
  for (const ReleaseTrial& trial : manifest.trials) stamp_owners.insert(trial.id);
  if (fs::is_directory(output_dir + "/params")) {
    for (const auto& entry : fs::directory_iterator(output_dir + "/params")) {
      const std::string name = entry.path().filename().string();
      if (entry.path().extension() != ".json") continue;
      const std::string stem = entry.path().stem().string();
      // "<trial>.<stage>[.<format>]", "library[.<style>]", "summary.<table>"; trial ids may hold '.'.
      bool owned = false;
      for (const std::string& owner : stamp_owners) owned = owned || stem == owner || stem.rfind(owner + ".", 0) == 0;
      if (owned) add("params/" + name, entry.path().string());
    }
  }
  for (const ReleaseTrial& trial : manifest.trials) {
    const std::string from = output_dir + "/trials/" + trial.id + "/", to = "trials/" + trial.id + "/";
    for (const char* file : {"motion.h5", "synergies.h5", "metrics.json"}) add(to + file, from + file);
    for (const std::string& format : manifest.exports) {
      const std::string& file = FindReleaseExportFormat(format)->file_name;
      add(to + file, from + file);
    }
  }
  return files;
}

std::vector<ReleaseFile> ListReleaseFolder(const std::string& folder) {
  std::vector<ReleaseFile> files;
  for (const auto& entry : fs::recursive_directory_iterator(folder)) {
    if (!entry.is_regular_file()) continue;
    files.push_back({fs::relative(entry.path(), folder).generic_string(), entry.path().string(), ""});
  }
  std::sort(files.begin(), files.end(), [](const ReleaseFile& a, const ReleaseFile& b) { return a.path < b.path; });
  return files;
}

bool IsDerivedReleaseFile(const std::string& path) {
  if (path == "README.md" || path == "quality.csv" || path == "SHA256SUMS") return true;
  return path.rfind("trials/", 0) == 0 && fs::path(path).filename() == "contact.csv";
}

void AddDerivedFiles(const ReleaseManifest& manifest, std::vector<ReleaseFile>& files) {
  std::map<std::string, std::string> disk;  // release path -> a readable file
  for (const ReleaseFile& file : files) {
    if (!file.disk_path.empty()) disk[file.path] = file.disk_path;
  }
  const auto disk_path = [&](const std::string& path) {
    const auto found = disk.find(path);
    if (found == disk.end()) throw DataError(Location::InFile(path), "missing from the release");
    return found->second;
  };
  std::vector<ReleaseFile> derived;
  for (const ReleaseTrial& trial : manifest.trials) {
    std::string csv = ContactFlagsCsv(disk_path("trials/" + trial.id + "/motion.h5"));
    if (!csv.empty()) derived.push_back({"trials/" + trial.id + "/contact.csv", "", std::move(csv)});
  }
  const Datasheet sheet = MakeDatasheet(manifest, files, disk_path);
  derived.push_back({"quality.csv", "", sheet.quality_csv});
  derived.push_back({"README.md", "", sheet.readme});
  files.insert(files.end(), derived.begin(), derived.end());
}

void AddChecksums(std::vector<ReleaseFile>& files) {
  std::sort(files.begin(), files.end(), [](const ReleaseFile& a, const ReleaseFile& b) { return a.path < b.path; });
  std::string sums;
  for (const ReleaseFile& file : files) {
    const std::string digest = file.disk_path.empty() ? Sha256Hex(file.bytes.data(), file.bytes.size()) : Sha256OfFile(file.disk_path);
    sums += digest + "  " + file.path + "\n";
  }
  files.push_back({"SHA256SUMS", "", sums});
  std::sort(files.begin(), files.end(), [](const ReleaseFile& a, const ReleaseFile& b) { return a.path < b.path; });
}

std::string ReleasePart(const std::string& path) {
  const std::string file = fs::path(path).filename().string();
  if (path.rfind("trials/", 0) == 0) {
    if (file == "motion.h5") return "motions (motion.h5)";
    if (file == "synergies.h5") return "synergies";
    if (file == "metrics.json") return "metrics";
    if (file == "contact.csv") return "contact flags";
    for (const ReleaseExportFormat& format : ReleaseExportFormats()) {
      if (file == format.file_name) return "export " + format.name;
    }
    return "trials, other";
  }
  if (path.rfind("library", 0) == 0) return "libraries";
  if (path.rfind("summary/", 0) == 0) return "summaries";
  if (path.rfind("params/", 0) == 0) return "parameters";
  if (path.rfind("robot/", 0) == 0) return "robot";
  return "datasheet, manifest, checksums";
}

ReleaseSizes WriteReleaseTar(const ReleaseManifest& manifest, const std::vector<ReleaseFile>& files, const std::string& tar_path) {
  const std::string root = ReleaseFolderName(manifest);
  // Folders first in name order, each before its contents: every path, and every folder above it, sorted.
  std::set<std::string> entries;
  std::set<std::string> folders = {root};
  for (const ReleaseFile& file : files) {
    entries.insert(root + "/" + file.path);
    for (fs::path parent = fs::path(file.path).parent_path(); !parent.empty(); parent = parent.parent_path()) {
      folders.insert(root + "/" + parent.generic_string());
    }
  }
  entries.insert(folders.begin(), folders.end());
  std::map<std::string, const ReleaseFile*> by_entry;
  for (const ReleaseFile& file : files) by_entry[root + "/" + file.path] = &file;
  std::map<std::string, uint64_t> parts;
  TarWriter tar(tar_path);
  for (const std::string& entry : entries) {
    const auto found = by_entry.find(entry);
    if (found == by_entry.end()) {
      tar.addDirectory(entry);
      continue;
    }
    const ReleaseFile& file = *found->second;
    if (file.disk_path.empty()) {
      tar.addBytes(entry, file.bytes);
      parts[ReleasePart(file.path)] += file.bytes.size();
    } else {
      tar.addFile(entry, file.disk_path);
      parts[ReleasePart(file.path)] += fs::file_size(file.disk_path);
    }
  }
  tar.commit();
  ReleaseSizes sizes;
  sizes.parts.assign(parts.begin(), parts.end());
  sizes.tar_bytes = tar.size();
  return sizes;
}

}  // namespace syn
