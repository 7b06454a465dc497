// Dataset manifests (manifests/*.toml): which captures make up an archive,
// how to label them, and the parameters of every stage.
//
//   name = "demo"                      # outputs go to outputs/<name>/
//   version = "0.1.0"                  # release version
//   root = "datasets/demo"             # capture files are relative to it (DATASET_ROOT= overrides)
//   model = "datasets/robots/unitree_g1/g1_29dof.urdf"
//   robot_map = "manifests/robots/g1.toml"
//   markerset = "manifests/markersets/cmu-bvh.toml"
//   [ingest]                           # defaults per stage, same names as the flags
//   drop_first_frame = true
//   [[trial]]
//   id = "02_01"                       # unique; names every output of the trial
//   subject = "02"
//   file = "02_01.bvh"
//   style = "walk"                     # the style library the trial joins (default: motion_class)
//   motion_class = "walk"
//   ingest = { drop_first_frame = false }   # per-trial overrides, per stage
//   up_axis = "y"                      # shorthand for a parameter only one stage has
//   licence = "..."  source = "..."   # of the captures, per manifest or per trial (common/release_manifest.h)
//   [release] exports = ["robot-csv", "mot"]   # syn-export files per trial (common/release_manifest.h);
//                                      # with licence, citation and the robot's licence for the datasheet
//   [retarget] mapping = "osc"         # kinematic (default): the retargeted motion goes on to segment;
//                                      # osc: syn-simulate's dynamic mapping runs in between ([simulate]
//                                      # holds its parameters, e.g. contact = "none"); per trial too
#pragma once

#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/release_manifest.h"

namespace syn {

// The parameters each stage accepts (flag names with '_' for '-'), so a
// manifest can be checked before anything runs.
struct StageParameterNames {
  std::string stage;
  std::vector<std::string> names;
};

struct ManifestTrial {
  int line = 0;
  std::string id;
  std::string subject;
  std::string file;          // as written, relative to the root
  std::string path;          // root/file
  std::string style;
  std::string motion_class;
  std::string genre;
  std::string mapping = "kinematic";  // "kinematic" or "osc" (syn-simulate between retarget and segment)
  int mapping_line = 0;
  std::map<std::string, nlohmann::json> parameters;  // stage -> {name: value}, defaults merged with overrides
};

struct Manifest {
  std::string path;
  std::string name;
  std::string version = "0.0.0";
  std::string description;
  std::string root;
  std::string model;
  std::string robot_map;
  std::string markerset;
  std::vector<ManifestTrial> trials;
  ReleaseManifest release;  // licences, sources, the per-trial exports (what `make release` ships)
};

// Parses and validates a manifest: unknown keys, unknown parameters, missing
// capture files and duplicate trial ids are DataErrors at manifest:line.
// `dataset_root` (non-empty) replaces the manifest's root.
[[nodiscard]] Manifest LoadManifest(const std::string& path, const std::string& dataset_root,
                                    const std::vector<StageParameterNames>& stages);

}  // namespace syn
