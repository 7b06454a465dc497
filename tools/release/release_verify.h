// `syn-release verify RELEASE.tar|DIR [--rebuild]`: the checks a user (or a reviewer) runs on a release.
// The first failed check throws a DataError naming the file inside the release and what differs:
//   1. SHA256SUMS: every listed file is present with that digest, and no file is unlisted;
//   2. every trial of manifest.toml is present with its motion, synergies, metrics and exports, and every
//      style library, summary, the URDF and the robot map;
//   3. every HDF5 file has the schema and schema version its name says (common/*_file.h), metrics.json
//      syn-evaluate's; every motion was made with the shipped URDF (model_sha256);
//   4. README.md, quality.csv and contact.csv are what this syn-release makes from the release's files
//      (skipped, with a note, when another synsculpt version made the release);
//   5. with --rebuild: the pipeline re-run from the captures (syn-plan + make in a scratch tree beside the
//      source tree, so recorded relative paths resolve the same) gives the same bytes, member by member.
#pragma once

#include <string>
#include <vector>

namespace syn {

struct VerifyOptions {
  bool rebuild = false;
  std::string source_dir = ".";  // the synsculpt tree whose manifests/, datasets/ the manifest names
  std::string bin_dir;           // the syn-* tools (default: syn-release's own folder)
  std::string dataset_root;      // default: the one provenance.json records
  int jobs = 2;                  // make -j for the rebuild
  bool keep_scratch = false;
};

struct VerifySummary {
  std::string release_folder;  // NAME-VERSION
  size_t files = 0;
  size_t trials = 0;
  std::vector<std::string> notes;  // checks skipped and why
  bool rebuilt = false;
};

// `release` is a tar (extracted into a temporary folder first) or an extracted release folder.
VerifySummary VerifyRelease(const std::string& release, const VerifyOptions& options);

}  // namespace syn
