// The files of a dataset release (NAME-VERSION/ inside the tar):
//
//   README.md                the datasheet (tools/release/datasheet.h)
//   quality.csv              per-trial quality figures (tools/release/trial_quality.h)
//   SHA256SUMS               `sha256sum -c` format, every other file
//   manifest.toml            the manifest the release was made from
//   provenance.json          tool version, dataset root, Debian versions of the numeric dependencies
//   robot/                   the URDF, the robot map, the URDF's licence file ([release] model_licence_file)
//   library.h5, library/     style libraries (syn-library)
//   summary/                 trials.csv, segments.csv (syn-summary)
//   params/                  the manifest's parameter stamps per stage and trial (syn-plan)
//   trials/ID/               motion.h5 (syn-retarget or syn-simulate), synergies.h5, metrics.json, the
//                            [release] exports (motion.robot.csv, ...), contact.csv when motion.h5 has
//                            contact flags
//
// README.md, quality.csv and contact.csv are derived from the other files only, so `syn-release verify`
// can make them again from a release and compare.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "common/release_manifest.h"

namespace syn {

struct ReleaseFile {
  std::string path;       // inside the release folder, '/'-separated
  std::string disk_path;  // where the bytes are; empty when `bytes` holds them
  std::string bytes;

  [[nodiscard]] std::string contents() const;  // reads disk_path when needed
};

// The files `make run` produced for the manifest, under `output_dir` (outputs/NAME), plus manifest.toml,
// provenance.json and robot/. A missing file is a DataError naming it (run `make run` first).
[[nodiscard]] std::vector<ReleaseFile> CollectPipelineFiles(const ReleaseManifest& manifest, const std::string& output_dir,
                                                            const std::string& provenance_json);

// Every file of a release folder (extracted), as ReleaseFiles pointing at the disk.
[[nodiscard]] std::vector<ReleaseFile> ListReleaseFolder(const std::string& folder);

// Names of the derived files (README.md, quality.csv, trials/*/contact.csv) and SHA256SUMS.
[[nodiscard]] bool IsDerivedReleaseFile(const std::string& path);

// Adds README.md, quality.csv and contact.csv files made from `files` (which must hold the pipeline files).
void AddDerivedFiles(const ReleaseManifest& manifest, std::vector<ReleaseFile>& files);

// Sorts the files by path and appends SHA256SUMS.
void AddChecksums(std::vector<ReleaseFile>& files);

// The size breakdown's group of a release path ("motions", "export robot-csv", "libraries", ...).
[[nodiscard]] std::string ReleasePart(const std::string& path);

// The release folder name, NAME-VERSION.
[[nodiscard]] std::string ReleaseFolderName(const ReleaseManifest& manifest);

// Writes the files as a deterministic tar of the folder ReleaseFolderName(manifest); returns per part
// {part, bytes} (file contents, sorted by part name) and the tar's total size.
struct ReleaseSizes {
  std::vector<std::pair<std::string, uint64_t>> parts;
  uint64_t tar_bytes = 0;
};
ReleaseSizes WriteReleaseTar(const ReleaseManifest& manifest, const std::vector<ReleaseFile>& files, const std::string& tar_path);

}  // namespace syn
