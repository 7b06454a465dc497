#include "tools/release/release_verify.h"

#include <sys/wait.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>

#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/file_bytes.h"
#include "common/intermediate_file.h"
#include "common/library_file.h"
#include "common/motion_file.h"
#include "common/release_manifest.h"
#include "common/sha256.h"
#include "common/synergies_file.h"
#include "common/version.h"
#include "stages/evaluate/evaluate.h"
#include "tools/release/release_contents.h"
#include "tools/release/tar_archive.h"

namespace syn {
namespace {
namespace fs = std::filesystem;

// A folder removed when it goes out of scope (unless kept).
class ScratchFolder {
 public:
  explicit ScratchFolder(fs::path path, bool keep = false) : path_(std::move(path)), keep_(keep) {
    fs::remove_all(path_);
    fs::create_directories(path_);
  }
  ~ScratchFolder() {
    std::error_code ignored;
    if (!keep_) fs::remove_all(path_, ignored);
  }
  ScratchFolder(const ScratchFolder&) = delete;
  ScratchFolder& operator=(const ScratchFolder&) = delete;
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
  bool keep_;
};

// Names a file of the release in errors: "RELEASE: FOLDER/PATH".
class Names {
 public:
  Names(std::string release, std::string folder) : release_(std::move(release)), folder_(std::move(folder)) {}
  Location at(const std::string& path) const { return Location::InFile(release_ + ": " + folder_ + "/" + path); }

 private:
  std::string release_, folder_;
};

std::string ShellQuoted(const std::string& word) {
  std::string quoted = "'";
  for (char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

// SHA256SUMS: every listed file present with its digest, nothing unlisted.
void CheckChecksums(const fs::path& folder, const Names& names, const std::vector<ReleaseFile>& files) {
  if (!fs::is_regular_file(folder / "SHA256SUMS")) throw DataError(names.at("SHA256SUMS"), "missing: a release lists its files' SHA-256 there");
  std::istringstream lines(ReadFileText((folder / "SHA256SUMS").string()));
  std::set<std::string> listed;
  int line_number = 0;
  for (std::string line; std::getline(lines, line);) {
    ++line_number;
    const Location at = Location::AtLine(names.at("SHA256SUMS").file, line_number);
    if (line.size() < 67 || line.substr(64, 2) != "  " || line.find_first_not_of("0123456789abcdef") < 64) {
      throw DataError(at, "expected '<64 hex digits>  <path>'");
    }
    const std::string digest = line.substr(0, 64), path = line.substr(66);
    if (!listed.insert(path).second) throw DataError(at, path + " is listed twice");
    if (!fs::is_regular_file(folder / path)) throw DataError(names.at(path), "listed in SHA256SUMS (line " + std::to_string(line_number) + ") but missing from the release");
    const std::string found = Sha256OfFile((folder / path).string());
    if (found != digest) {
      throw DataError(names.at(path), "SHA-256 " + found + " differs from SHA256SUMS line " + std::to_string(line_number) +
                                          " (" + digest + "): the file was changed");
    }
  }
  for (const ReleaseFile& file : files) {
    if (file.path != "SHA256SUMS" && !listed.count(file.path)) throw DataError(names.at(file.path), "not listed in SHA256SUMS");
  }
}

// Every trial of the manifest, with what the release promises for it.
void CheckTrialsPresent(const fs::path& folder, const Names& names, const ReleaseManifest& manifest) {
  std::vector<std::string> required = {"README.md", "quality.csv", "provenance.json", "library.h5", "summary/trials.csv",
                                       "summary/segments.csv"};
  for (const std::string* robot_file : {&manifest.model, &manifest.robot_map, &manifest.model_licence_file}) {
    if (!robot_file->empty()) required.push_back("robot/" + fs::path(*robot_file).filename().string());
  }
  std::set<std::string> styles;
  for (const ReleaseTrial& trial : manifest.trials) styles.insert(trial.style);
  for (const std::string& style : styles) required.push_back("library/" + style + ".h5");
  for (const std::string& path : required) {
    if (!fs::is_regular_file(folder / path)) throw DataError(names.at(path), "missing from the release");
  }
  for (const ReleaseTrial& trial : manifest.trials) {
    std::vector<std::string> files = {"motion.h5", "synergies.h5", "metrics.json"};
    for (const std::string& format : manifest.exports) files.push_back(FindReleaseExportFormat(format)->file_name);
    for (const std::string& file : files) {
      const std::string path = "trials/" + trial.id + "/" + file;
      if (!fs::is_regular_file(folder / path)) {
        throw DataError(names.at(path), "missing: manifest.toml line " + std::to_string(trial.line) + " lists trial '" + trial.id + "'");
      }
    }
  }
}

// Schema and version of every intermediate; motions made with the shipped URDF.
void CheckSchemas(const fs::path& folder, const Names& names, const ReleaseManifest& manifest, const std::vector<ReleaseFile>& files) {
  const std::string urdf_sha = manifest.model.empty() ? "" : Sha256OfFile((folder / ("robot/" + fs::path(manifest.model).filename().string())).string());
  for (const ReleaseFile& file : files) {
    const std::string name = fs::path(file.path).filename().string();
    try {
      if (name == "motion.h5") {
        const MotionData motion = ReadMotionFile(file.disk_path);
        if (!urdf_sha.empty() && motion.model_sha256 != urdf_sha) {
          throw DataError(names.at(file.path), "made with a URDF of SHA-256 " + motion.model_sha256 + ", not the shipped " + urdf_sha);
        }
      } else if (name == "synergies.h5") {
        IntermediateReader reader(file.disk_path, kSynergiesSchema, kSynergiesSchemaVersion);
      } else if (file.path.rfind("library", 0) == 0 && fs::path(name).extension() == ".h5") {
        IntermediateReader reader(file.disk_path, kLibrarySchema, kLibrarySchemaVersion);
      } else if (fs::path(name).extension() == ".h5") {
        throw DataError(names.at(file.path), "an HDF5 file a release does not hold");
      } else if (name == "metrics.json") {
        const nlohmann::json metrics = nlohmann::json::parse(ReadFileText(file.disk_path));
        if (metrics.value("schema", std::string()) != kMetricsSchema || metrics.value("schema_version", -1) != kMetricsSchemaVersion) {
          throw DataError(names.at(file.path), "schema " + metrics.value("schema", std::string("(none)")) + " version " +
                                                   std::to_string(metrics.value("schema_version", -1)) + ", expected " +
                                                   kMetricsSchema + " version " + std::to_string(kMetricsSchemaVersion));
        }
      } else if (fs::path(name).extension() == ".json") {
        const nlohmann::json parsed = nlohmann::json::parse(ReadFileText(file.disk_path));
      }
    } catch (const nlohmann::json::exception& error) {
      throw DataError(names.at(file.path), std::string("not valid JSON: ") + error.what());
    } catch (const DataError& error) {
      if (error.where().file.rfind(names.at("").file, 0) == 0) throw;  // already names the release file
      throw DataError(names.at(file.path), error.message());
    }
  }
}

// The first byte where two files differ, or -1.
int64_t FirstDifference(const std::string& a, const std::string& b) {
  const size_t common = std::min(a.size(), b.size());
  for (size_t i = 0; i < common; ++i) {
    if (a[i] != b[i]) return static_cast<int64_t>(i);
  }
  return a.size() == b.size() ? -1 : static_cast<int64_t>(common);
}

std::string Hex(unsigned char byte) {
  static const char* digits = "0123456789abcdef";
  return std::string("0x") + digits[byte >> 4] + digits[byte & 15];
}

// Compares the release's files with `expected` (same paths), naming the first file and byte that differ.
void CompareFiles(const Names& names, const std::vector<ReleaseFile>& release, const std::vector<ReleaseFile>& expected,
                  const std::string& what) {
  std::map<std::string, const ReleaseFile*> ours;
  for (const ReleaseFile& file : release) ours[file.path] = &file;
  // SHA256SUMS last: a changed file changes it too, and the file is the news.
  std::vector<const ReleaseFile*> in_order;
  for (const ReleaseFile& file : expected) in_order.push_back(&file);
  std::stable_partition(in_order.begin(), in_order.end(), [](const ReleaseFile* file) { return file->path != "SHA256SUMS"; });
  for (const ReleaseFile* expected_file : in_order) {
    const ReleaseFile& file = *expected_file;
    const auto found = ours.find(file.path);
    if (found == ours.end()) throw DataError(names.at(file.path), "missing from the release, but " + what + " has it");
    const std::string have = found->second->contents(), want = file.contents();
    const int64_t at = FirstDifference(have, want);
    if (at < 0) continue;
    std::string detail = have.size() != want.size() && at == static_cast<int64_t>(std::min(have.size(), want.size()))
                             ? "size " + std::to_string(have.size()) + " bytes, " + what + " has " + std::to_string(want.size())
                             : Hex(static_cast<unsigned char>(have[static_cast<size_t>(at)])) + " here, " +
                                   Hex(static_cast<unsigned char>(want[static_cast<size_t>(at)])) + " in " + what;
    throw DataError(names.at(file.path), "differs from " + what + " at byte offset " + std::to_string(at) + " (" + detail + ")");
  }
  std::set<std::string> theirs;
  for (const ReleaseFile& file : expected) theirs.insert(file.path);
  for (const ReleaseFile& file : release) {
    if (!theirs.count(file.path)) throw DataError(names.at(file.path), "in the release, but not in " + what);
  }
}

int RunLogged(const std::string& command, const fs::path& log) {
  const int status = std::system((command + " > " + ShellQuoted(log.string()) + " 2>&1").c_str());
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128;
}

std::string Tail(const fs::path& log) {
  const std::string text = ReadFileText(log.string());
  return text.size() > 3000 ? "..." + text.substr(text.size() - 3000) : text;
}

// Re-runs the pipeline for the release's manifest in a scratch tree beside the source tree and compares.
void Rebuild(const fs::path& folder, const Names& names, const ReleaseManifest& manifest, const std::vector<ReleaseFile>& files,
             const VerifyOptions& options) {
  const fs::path source = fs::absolute(options.source_dir).lexically_normal();
  const fs::path bin = fs::absolute(options.bin_dir);
  std::string dataset_root = options.dataset_root;
  if (dataset_root.empty()) {
    const nlohmann::json provenance = nlohmann::json::parse(ReadFileText((folder / "provenance.json").string()));
    dataset_root = provenance.value("dataset_root", manifest.root);
  }
  // A sibling of the source tree, so that "../shared/..." roots resolve the same; every top-level entry but
  // outputs/ is a symlink into the source tree, and intermediate files record the same relative paths.
  const fs::path scratch_path = source.parent_path() / (".syn-release-rebuild-" + manifest.name + "-" + std::to_string(::getpid()));
  ScratchFolder scratch(scratch_path, options.keep_scratch);
  for (const auto& entry : fs::directory_iterator(source)) {
    if (entry.path().filename() == "outputs") continue;
    fs::create_directory_symlink(entry.path(), scratch.path() / entry.path().filename());
  }
  fs::copy_file(folder / "manifest.toml", scratch.path() / "release-manifest.toml");
  const std::string in_scratch = "cd " + ShellQuoted(scratch.path().string()) + " && ";
  const std::string root_flag = " --dataset-root " + ShellQuoted(dataset_root);
  const fs::path log = scratch.path() / "rebuild.log";
  const std::string rules = "outputs/" + manifest.name + "/rules.mk";
  if (RunLogged(in_scratch + ShellQuoted((bin / "syn-plan").string()) + " release-manifest.toml -o " + rules +
                    " --outputs outputs --stage-bin " + ShellQuoted(bin.string()) + root_flag, log) != 0) {
    throw DataError(names.at("manifest.toml"), "syn-plan failed in the rebuild (" + scratch.path().string() + "):\n" + Tail(log));
  }
  if (RunLogged(in_scratch + "make -s -j" + std::to_string(std::max(1, options.jobs)) + " -f " + rules +
                    " SYN_BIN=" + ShellQuoted(bin.string()) + " all", log) != 0) {
    throw DataError(names.at("manifest.toml"), "the pipeline failed in the rebuild (" + scratch.path().string() + "):\n" + Tail(log));
  }
  const std::string tar = "rebuilt.tar";
  if (RunLogged(in_scratch + ShellQuoted((bin / "syn-release").string()) + " build release-manifest.toml --outputs outputs -o " +
                    tar + root_flag, log) != 0) {
    throw DataError(names.at("manifest.toml"), "syn-release build failed in the rebuild:\n" + Tail(log));
  }
  const fs::path extracted = scratch.path() / "rebuilt";
  fs::create_directories(extracted);
  ExtractTar((scratch.path() / tar).string(), extracted.string());
  CompareFiles(names, files, ListReleaseFolder((extracted / ReleaseFolderName(manifest)).string()), "the rebuilt release");
}

}  // namespace

VerifySummary VerifyRelease(const std::string& release, const VerifyOptions& options) {
  VerifySummary summary;
  std::unique_ptr<ScratchFolder> extracted;
  fs::path folder = release;
  if (fs::is_regular_file(release)) {
    extracted = std::make_unique<ScratchFolder>(fs::temp_directory_path() / ("syn-release-verify-" + std::to_string(::getpid())));
    const std::vector<TarMember> members = ExtractTar(release, extracted->path().string());
    std::set<std::string> tops;
    for (const TarMember& member : members) tops.insert(member.name.substr(0, member.name.find('/')));
    if (tops.size() != 1) throw DataError(Location::InFile(release), "a release tar holds one folder, NAME-VERSION; this one holds " + std::to_string(tops.size()) + " top-level entries");
    folder = extracted->path() / *tops.begin();
  } else if (!fs::is_directory(release)) {
    throw DataError(Location::InFile(release), "not found (expected a release tar or an extracted release folder)");
  }
  summary.release_folder = folder.filename().string();
  const Names names(release, summary.release_folder);
  const std::vector<ReleaseFile> files = ListReleaseFolder(folder.string());
  summary.files = files.size();

  CheckChecksums(folder, names, files);
  if (!fs::is_regular_file(folder / "manifest.toml")) throw DataError(names.at("manifest.toml"), "missing from the release");
  ReleaseManifest manifest;
  try {
    manifest = ReadReleaseManifest((folder / "manifest.toml").string());
  } catch (const DataError& error) {
    throw DataError(names.at("manifest.toml"), error.where().ToString() + ": " + error.message());
  }
  if (ReleaseFolderName(manifest) != summary.release_folder) {
    throw DataError(names.at("manifest.toml"), "names the release " + ReleaseFolderName(manifest) + ", but its folder is " + summary.release_folder);
  }
  summary.trials = manifest.trials.size();
  CheckTrialsPresent(folder, names, manifest);
  CheckSchemas(folder, names, manifest, files);

  // The datasheet, quality table and contact flags, made again from the release's own files.
  const nlohmann::json provenance = nlohmann::json::parse(ReadFileText((folder / "provenance.json").string()));
  const std::string made_by = provenance.value("tool", std::string());
  if (made_by == std::string("synsculpt ") + kVersion) {
    std::vector<ReleaseFile> pipeline_files, derived_files;
    for (const ReleaseFile& file : files) (IsDerivedReleaseFile(file.path) ? derived_files : pipeline_files).push_back(file);
    std::vector<ReleaseFile> expected = pipeline_files;
    AddDerivedFiles(manifest, expected);
    std::vector<ReleaseFile> expected_derived;
    for (const ReleaseFile& file : expected) {
      if (IsDerivedReleaseFile(file.path)) expected_derived.push_back(file);
    }
    derived_files.erase(std::remove_if(derived_files.begin(), derived_files.end(), [](const ReleaseFile& f) { return f.path == "SHA256SUMS"; }),
                        derived_files.end());
    CompareFiles(names, derived_files, expected_derived, "what syn-release makes from the release's files");
  } else {
    summary.notes.push_back("README.md, quality.csv and contact.csv not made again: the release was made by " +
                            (made_by.empty() ? std::string("an unknown tool") : made_by) + ", this is synsculpt " + kVersion);
  }

  if (options.rebuild) {
    Rebuild(folder, names, manifest, files, options);
    summary.rebuilt = true;
  }
  return summary;
}

}  // namespace syn
