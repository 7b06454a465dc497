// What a dataset release says about itself, read from its manifest (manifests/*.toml): the licence and
// source of every capture, the release's own licence and citation, the robot's licence, and which motion
// exports each trial ships. syn-plan reads it to plan the export jobs and to warn about missing licences;
// syn-release reads it to assemble, describe and verify the release. The rest of the manifest (stage
// parameters) is syn-plan's (stages/plan/manifest.h) and is skipped here.
//
//   licence = "CMU Graphics Lab Motion Capture Database terms: free for all uses, ..."   # every capture
//   source = "mocap.cs.cmu.edu (cgspeed BVH conversions)"                               # every capture
//   [release]
//   licence = "CC-BY-4.0"                 # the release's own licence (default: "unknown")
//   citation = "..."                      # how to cite it (default: the synsculpt software citation)
//   exports = ["robot-csv", "unitree-csv", "mjlab-npz", "mot"]   # per trial, made by syn-export
//   model_licence = "BSD-3-Clause, Unitree Robotics"   # the robot URDF's licence (default: "unknown")
//   model_source = "github.com/unitreerobotics/unitree_rl_gym @ 276801e"
//   model_licence_file = "datasets/robots/unitree_g1/LICENSE"   # shipped beside the URDF
//   [[trial]]
//   licence = "..."  source = "..."       # per-trial overrides of the manifest's
#pragma once

#include <string>
#include <vector>

namespace syn {

// One motion export format of syn-export as the release ships it.
struct ReleaseExportFormat {
  std::string name;        // syn-export's --format
  std::string file_name;   // the file in trials/<id>/
  std::string aliases;     // other names the manifest accepts, comma-separated
};

// Every syn-export format, in the order the datasheet lists them.
[[nodiscard]] const std::vector<ReleaseExportFormat>& ReleaseExportFormats();

// The format named `name` or one of its aliases ("lafan1-csv" = unitree-csv, "beyondmimic-npz" =
// mjlab-npz); nullptr for an unknown name.
[[nodiscard]] const ReleaseExportFormat* FindReleaseExportFormat(const std::string& name);

struct ReleaseTrial {
  int line = 0;
  std::string id;
  std::string subject;
  std::string motion_class;
  std::string style;     // as syn-plan resolves it: style, else motion_class, else "default"
  std::string licence;   // the trial's, else the manifest's; empty = none given
  std::string source;
};

struct ReleaseManifest {
  std::string path;
  std::string name;
  std::string version = "0.0.0";  // syn-plan's default too
  std::string description;
  std::string root;
  std::string model;
  std::string robot_map;
  std::string licence;  // of every capture unless a trial names its own
  std::string source;
  std::string release_licence;
  std::string citation;
  std::vector<std::string> exports;  // syn-export format names (aliases resolved), in manifest order
  std::string model_licence;
  std::string model_source;
  std::string model_licence_file;
  std::vector<ReleaseTrial> trials;

  // "file:line: trial 'X' names no licence ..." for every trial without one, and one for the robot.
  [[nodiscard]] std::vector<std::string> licenceWarnings() const;
};

// Reads the release-related keys of a manifest; other keys are left to syn-plan. A malformed [release]
// table, an unknown export format or a non-string licence is a DataError at manifest:line.
[[nodiscard]] ReleaseManifest ReadReleaseManifest(const std::string& path);
[[nodiscard]] ReleaseManifest ParseReleaseManifest(const std::string& toml_text, const std::string& path);

// The keys ReadReleaseManifest reads at the top level and in a trial (besides syn-plan's own), for
// syn-plan's unknown-key check.
inline constexpr const char* kReleaseManifestTable = "release";
[[nodiscard]] bool IsReleaseManifestKey(const std::string& key);

}  // namespace syn
