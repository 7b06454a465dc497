// The release's datasheet (README.md at its root, in the spirit of "Datasheets for Datasets", Gebru et
// al. 2021) and its quality table (quality.csv): what the dataset is, the robot and its URDF (SHA-256 and
// licence), the pipeline version and parameters, one row per trial (subject, class, style, duration,
// frames, quality), totals, the columns of every export, how to cite it, and the licence and source of
// every capture. Everything is read from the release's own files, so verify can make it again.
#pragma once

#include <functional>
#include <string>
#include <vector>

#include "common/release_manifest.h"
#include "tools/release/release_contents.h"

namespace syn {

struct Datasheet {
  std::string readme;
  std::string quality_csv;
};

// `disk_path(release path)` gives a readable file for a release path (throws DataError when missing).
[[nodiscard]] Datasheet MakeDatasheet(const ReleaseManifest& manifest, const std::vector<ReleaseFile>& files,
                                      const std::function<std::string(const std::string&)>& disk_path);

// The totals line of the datasheet, parsed back (for tests and tools): "**Totals:** N trials, S subjects,
// F frames, D s (H h) of robot motion."
inline constexpr const char* kTotalsPrefix = "**Totals:** ";

}  // namespace syn
