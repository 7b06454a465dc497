// Turning a manifest into make rules: one target per trial per stage, each
// depending on its inputs, its parameter stamp file and the stage binary, so
// `make -j` runs trials in parallel and rebuilds exactly what a change affects.
#pragma once

#include <string>
#include <vector>

#include "stages/plan/manifest.h"

namespace syn {

// One stage run: `command` reads `inputs` and writes `output`.
struct PlannedJob {
  std::string stage;
  std::string trial;
  std::string output;
  std::vector<std::string> inputs;
  std::string stamp;       // parameter stamp file (a prerequisite)
  std::string stamp_text;  // its content: the resolved parameters as canonical JSON
  std::string command;     // with $(SYN_BIN) for the binary
};

struct Plan {
  std::string output_dir;  // outputs/<name>
  std::vector<PlannedJob> jobs;
};

// The jobs for every trial and stage that exists today.
[[nodiscard]] Plan MakePlan(const Manifest& manifest, const std::string& outputs_root);

// The command-line flags for a parameter object: true -> --name, false -> (nothing),
// other values -> --name value; '_' in names becomes '-'. Sorted by name.
[[nodiscard]] std::string FlagsFor(const nlohmann::json& parameters);

// Writes each job's stamp file only if its content changed (so make sees a
// new time exactly when the parameters changed), then the rules file itself
// (also only if changed). Returns the number of stamp files rewritten.
int WritePlan(const Plan& plan, const Manifest& manifest, const std::string& rules_path);

}  // namespace syn
