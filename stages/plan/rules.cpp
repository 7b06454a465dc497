#include "stages/plan/rules.h"

#include <filesystem>
#include <map>
#include <fstream>
#include <sstream>

#include "common/error.h"
#include "common/file_bytes.h"
#include "common/intermediate_file.h"
#include "common/version.h"

namespace syn {
namespace {

// Quotes a word for the shell unless it is plainly safe.
std::string ShellWord(const std::string& word) {
  const bool safe = !word.empty() && word.find_first_not_of(
                                         "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_-./=:+,") ==
                                         std::string::npos;
  if (safe) return word;
  std::string quoted = "'";
  for (char c : word) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

// make treats '$' specially in recipes.
std::string MakeEscaped(const std::string& text) {
  std::string escaped;
  for (char c : text) escaped += c == '$' ? std::string("$$") : std::string(1, c);
  return escaped;
}

std::string ValueText(const nlohmann::json& value) {
  if (value.is_string()) return value.get<std::string>();
  return value.dump();
}

// Writes `text` to `path` unless the file already holds exactly that.
bool WriteIfChanged(const std::string& path, const std::string& text) {
  {
    std::ifstream existing(path, std::ios::binary);
    if (existing) {
      std::ostringstream current;
      current << existing.rdbuf();
      if (current.str() == text) return false;
    }
  }
  std::error_code error;
  std::filesystem::create_directories(std::filesystem::path(path).parent_path(), error);
  if (error) {
    throw DataError(Location::InFile(path), "cannot create its folder " +
                                                std::filesystem::path(path).parent_path().string() + ": " +
                                                error.message());
  }
  WriteFileAtomically(path, text);
  return true;
}

}  // namespace

std::string FlagsFor(const nlohmann::json& parameters) {
  std::string flags;
  for (const auto& [name, value] : parameters.items()) {  // nlohmann objects iterate sorted
    std::string flag = "--" + name;
    std::replace(flag.begin(), flag.end(), '_', '-');
    if (value.is_boolean()) {
      if (value.get<bool>()) flags += " " + flag;
      continue;
    }
    flags += " " + flag + " " + ShellWord(ValueText(value));
  }
  return flags;
}

namespace {

// A job running `syn-<stage> ARGUMENTS -o $@ EXTRA FLAGS(parameters)`, whose stamp file holds `parameters`.
PlannedJob MakeJob(const std::string& output_dir, const std::string& stage, const std::string& name,
                   const std::string& output, std::vector<std::string> inputs, const std::string& arguments,
                   const std::string& extra, const nlohmann::json& parameters, const std::string& stamp_name) {
  PlannedJob job;
  job.stage = stage;
  job.trial = name;
  job.output = output;
  job.inputs = std::move(inputs);
  job.stamp = output_dir + "/params/" + stamp_name + ".json";
  job.stamp_text = CanonicalJson(parameters) + "\n";
  job.command = "$(SYN_BIN)/syn-" + stage + " " + arguments + " -o $@" + extra + MakeEscaped(FlagsFor(parameters));
  return job;
}

std::string Joined(const std::vector<std::string>& words) {
  std::string text;
  for (const std::string& word : words) text += (text.empty() ? "" : " ") + word;
  return text;
}

}  // namespace

Plan MakePlan(const Manifest& manifest, const std::string& outputs_root) {
  Plan plan;
  const std::string& out = plan.output_dir = outputs_root + "/" + manifest.name;
  const bool has_robot = !manifest.model.empty() && !manifest.robot_map.empty() && !manifest.markerset.empty();
  const std::string model = MakeEscaped(ShellWord(manifest.model));
  std::map<std::string, std::vector<std::string>> synergies_by_style;
  std::vector<std::string> all_synergies, all_metrics;
  for (const ManifestTrial& trial : manifest.trials) {
    const std::string dir = out + "/trials/" + trial.id;
    const auto parameters_of = [&](const std::string& stage) {
      const auto found = trial.parameters.find(stage);
      return found == trial.parameters.end() ? nlohmann::json::object() : found->second;
    };
    const std::string markers = dir + "/markers.h5", motion = dir + "/motion.h5";
    const std::string segments = dir + "/segments.h5", synergies = dir + "/synergies.h5";
    plan.jobs.push_back(MakeJob(out, "ingest", trial.id, markers, {trial.path}, MakeEscaped(ShellWord(trial.path)), "",
                                parameters_of("ingest"), trial.id + ".ingest"));
    if (!has_robot) continue;
    // The dynamic mapping (paper): syn-simulate turns the kinematic motion into the simulated one, and
    // everything downstream reads the simulated motion under the same name.
    const bool simulated = trial.mapping == "osc";
    const std::string retargeted = simulated ? dir + "/kinematic_motion.h5" : motion;
    plan.jobs.push_back(MakeJob(out, "retarget", trial.id, retargeted,
                                {markers, manifest.model, manifest.robot_map, manifest.markerset}, markers,
                                " --model " + model + " --robot-map " + MakeEscaped(ShellWord(manifest.robot_map)) +
                                    " --markerset " + MakeEscaped(ShellWord(manifest.markerset)),
                                parameters_of("retarget"), trial.id + ".retarget"));
    if (simulated) {
      nlohmann::json simulate_parameters = parameters_of("simulate");
      const nlohmann::json retarget_parameters = parameters_of("retarget");
      // The simulation loads the model as the retargeting did.
      if (!simulate_parameters.contains("floating_base") && retarget_parameters.contains("floating_base")) {
        simulate_parameters["floating_base"] = retarget_parameters["floating_base"];
      }
      plan.jobs.push_back(MakeJob(out, "simulate", trial.id, motion, {retargeted, manifest.model, manifest.robot_map},
                                  retargeted,
                                  " --model " + model + " --robot-map " + MakeEscaped(ShellWord(manifest.robot_map)),
                                  simulate_parameters, trial.id + ".simulate"));
    }
    plan.jobs.push_back(MakeJob(out, "segment", trial.id, segments, {motion, manifest.model}, motion, " --model " + model,
                                parameters_of("segment"), trial.id + ".segment"));
    // The trial's labels travel with its synergies into the libraries and summaries.
    nlohmann::json synergy_parameters = parameters_of("synergies");
    synergy_parameters["subject"] = trial.subject;
    synergy_parameters["trial"] = trial.id;
    synergy_parameters["style"] = trial.style;
    synergy_parameters["motion_class"] = trial.motion_class;
    plan.jobs.push_back(MakeJob(out, "synergies", trial.id, synergies, {motion, segments}, motion + " " + segments, "",
                                synergy_parameters, trial.id + ".synergies"));
    plan.jobs.push_back(MakeJob(out, "evaluate", trial.id, dir + "/metrics.json",
                                {motion, synergies, manifest.model, manifest.robot_map},
                                motion + " --synergies " + synergies,
                                " --model " + model + " --robot-map " + MakeEscaped(ShellWord(manifest.robot_map)),
                                parameters_of("evaluate"), trial.id + ".evaluate"));
    // The motion in the formats the release ships ([release] exports), loaded as the retargeting did.
    for (const std::string& format : manifest.release.exports) {
      nlohmann::json export_parameters = {{"format", format}};
      const nlohmann::json retarget_parameters = parameters_of("retarget");
      // syn-export has no "map" (the robot map's choice, syn-retarget's default): its "auto" then decides.
      if (retarget_parameters.contains("floating_base") && retarget_parameters["floating_base"] != "map") {
        export_parameters["floating_base"] = retarget_parameters["floating_base"];
      }
      plan.jobs.push_back(MakeJob(out, "export", trial.id + "." + format, dir + "/" + FindReleaseExportFormat(format)->file_name,
                                  {motion, manifest.model}, motion, " --model " + model, export_parameters,
                                  trial.id + ".export." + format));
    }
    synergies_by_style[trial.style].push_back(synergies);
    all_synergies.push_back(synergies);
    all_metrics.push_back(dir + "/metrics.json");
  }
  if (all_synergies.empty()) return plan;
  // Archive-wide stages take the manifest's defaults (every trial carries a copy; overrides are per trial).
  const auto found = manifest.trials.front().parameters.find("library");
  const nlohmann::json library_parameters =
      found == manifest.trials.front().parameters.end() ? nlohmann::json::object() : found->second;
  // One library per style, rebuilt when any of its trials' synergies change.
  for (const auto& [style, files] : synergies_by_style) {
    plan.jobs.push_back(MakeJob(out, "library", style, out + "/library/" + style + ".h5", files, Joined(files),
                                " --style " + MakeEscaped(ShellWord(style)), library_parameters, "library." + style));
  }
  // Every style in one file: what compose scripts that mix styles read.
  plan.jobs.push_back(MakeJob(out, "library", "all-styles", out + "/library.h5", all_synergies, Joined(all_synergies),
                              "", library_parameters, "library"));
  for (const std::string table : {"trials", "segments"}) {
    std::vector<std::string> inputs = all_synergies;
    inputs.insert(inputs.end(), all_metrics.begin(), all_metrics.end());
    plan.jobs.push_back(MakeJob(out, "summary", table, out + "/summary/" + table + ".csv", inputs,
                                Joined(all_synergies) + " --metrics " + Joined(all_metrics), " --table " + table,
                                nlohmann::json::object(), "summary." + table));
  }
  return plan;
}

int WritePlan(const Plan& plan, const Manifest& manifest, const std::string& rules_path) {
  int rewritten = 0;
  std::ostringstream rules;
  rules << "# Generated by syn-plan " << kVersion << " from " << manifest.path
        << ". Do not edit: `make run MANIFEST=...` regenerates it.\n"
        << "SHELL := /bin/bash\n"
        << "SYN_BIN ?= build/bin\n"
        << "# A stage's own messages go to OUTPUT.log; the terminal gets one line per finished job.\n"
        << "syn_start = start=$$EPOCHREALTIME\n"
        << "syn_done = printf '%-10s %-28s %7.2f s\\n' $(1) $(2) $$(awk \"BEGIN{print $$EPOCHREALTIME - $$start}\")\n"
        << "syn_failed = { cat $@.log >&2; echo \"make: $(1) $(2) failed (log: $@.log)\" >&2; exit 1; }\n"
        << "# How a job is started: directly here; CLUSTER=slurm adds tools/slurm/launch.mk, which makes each job an\n"
        << "# srun step. A launcher can report success for a step that never ran, so a job also fails unless its\n"
        << "# output exists and no prerequisite is newer.\n"
        << "syn_launch ?=\n"
        << "syn_wrote_output = { [ -f $@ ] && [ -z \"$$(find $^ -newer $@ 2>/dev/null)\" ] || "
           "{ echo \"$@ was not written (or is older than a prerequisite)\" >> $@.log; false; }; }\n"
        << ".DELETE_ON_ERROR:\n"
        << ".PHONY: all\n"
        << "all:";
  for (const PlannedJob& job : plan.jobs) rules << " \\\n  " << job.output;
  rules << "\n\n";
  for (const PlannedJob& job : plan.jobs) {
    if (WriteIfChanged(job.stamp, job.stamp_text)) ++rewritten;
    rules << job.output << ":";
    for (const std::string& input : job.inputs) rules << " " << input;
    rules << " " << job.stamp << " $(SYN_BIN)/syn-" << job.stage << "\n"
          << "\t@mkdir -p $(@D)\n"
          << "\t@$(syn_start); $(call syn_launch," << job.stage << "," << job.trial << ") " << job.command
          << " 2> $@.log && $(syn_wrote_output) && $(call syn_done," << job.stage << "," << job.trial
          << ") || $(call syn_failed," << job.stage << "," << job.trial << ")\n\n";
  }
  WriteIfChanged(rules_path, rules.str());
  return rewritten;
}

}  // namespace syn
