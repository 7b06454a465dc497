#include "stages/plan/stage_parameters.h"

#include <algorithm>
#include <array>
#include <cstdio>
#include <filesystem>
#include <memory>
#include <set>
#include <utility>

#include <nlohmann/json.hpp>

#include "common/error.h"
#include "stages/plan/rules.h"

namespace syn {
namespace {

// Runs `command`; its standard output and exit status.
std::pair<std::string, int> Run(const std::string& command, const std::string& tool) {
  std::unique_ptr<FILE, int (*)(FILE*)> pipe(popen(command.c_str(), "r"), pclose);
  if (!pipe) throw DataError(Location::InFile(tool), "could not run it");
  std::string output;
  std::array<char, 4096> buffer;
  size_t read = 0;
  while ((read = fread(buffer.data(), 1, buffer.size(), pipe.get())) > 0) output.append(buffer.data(), read);
  return {output, pclose(pipe.release())};
}

// Runs `command` and returns its standard output; throws DataError when it fails.
std::string OutputOf(const std::string& command, const std::string& tool) {
  const auto [output, status] = Run(command, tool);
  if (status != 0) throw DataError(Location::InFile(tool), "--print-parameters failed (exit status " + std::to_string(status) + ")");
  return output;
}

// The first line of a tool's complaint, without its "syn-x: usage error: " prefix.
std::string FirstLineOf(std::string text, const std::string& tool_name) {
  text = text.substr(0, text.find('\n'));
  for (const std::string& prefix : {tool_name + ": usage error: ", tool_name + ": error: "}) {
    if (text.rfind(prefix, 0) == 0) return text.substr(prefix.size());
  }
  return text;
}

StageParameterNames Query(const std::string& bin_dir, const std::string& stage, const std::vector<std::string>& excluded) {
  const std::string tool = bin_dir + "/syn-" + stage;
  if (!std::filesystem::exists(tool)) {
    throw DataError(Location::InFile(tool), "stage tool not found: build it first (make build)");
  }
  nlohmann::json parameters;
  try {
    parameters = nlohmann::json::parse(OutputOf("'" + tool + "' --print-parameters 2>/dev/null", tool));
  } catch (const nlohmann::json::parse_error& error) {
    throw DataError(Location::InFile(tool), std::string("--print-parameters printed no JSON: ") + error.what());
  }
  if (!parameters.is_object()) throw DataError(Location::InFile(tool), "--print-parameters printed no JSON object");
  StageParameterNames names{stage, {}};
  for (const auto& item : parameters.items()) {
    if (std::find(excluded.begin(), excluded.end(), item.key()) == excluded.end()) names.names.push_back(item.key());
  }
  return names;
}

}  // namespace

std::vector<StageParameterNames> QueryStageParameters(const std::string& bin_dir) {
  return {Query(bin_dir, "ingest", {}),
          Query(bin_dir, "retarget", {}),
          Query(bin_dir, "simulate", {}),
          Query(bin_dir, "segment", {}),
          Query(bin_dir, "synergies", {"subject", "trial", "style", "motion_class"}),
          Query(bin_dir, "evaluate", {}),
          Query(bin_dir, "library", {"style"}),
          // The subject of `make power-ratio`'s human model (syn-human): a manifest table, not a per-trial job.
          StageParameterNames{"human", {"height", "mass", "sex"}}};
}

void CheckParameterValues(const Manifest& manifest, const std::string& bin_dir) {
  std::set<std::string> checked;
  for (const ManifestTrial& trial : manifest.trials) {
    for (const char* stage_name : {"ingest", "retarget", "simulate", "segment", "synergies", "evaluate"}) {
      const std::string stage = stage_name;
      if (stage == "simulate" && trial.mapping != "osc") continue;
      const auto found = trial.parameters.find(stage);
      if (found == trial.parameters.end() || found->second.empty()) continue;
      const std::string flags = FlagsFor(found->second);
      if (!checked.insert(stage + flags).second) continue;
      const std::string tool = bin_dir + "/syn-" + stage;
      // stderr only: the JSON on stdout is not needed.
      const auto [complaint, status] = Run("'" + tool + "' --print-parameters" + flags + " 2>&1 >/dev/null", tool);
      if (status == 0) continue;
      throw DataError(Location::AtLine(manifest.path, trial.line),
                      "trial " + trial.id + ": syn-" + stage + " refuses its [" + stage + "] parameters:" + flags +
                          ": " + FirstLineOf(complaint, "syn-" + stage));
    }
  }
}

std::string OwnExecutableFolder() {
  std::error_code error;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
  return error ? std::string(".") : self.parent_path().string();
}

}  // namespace syn
