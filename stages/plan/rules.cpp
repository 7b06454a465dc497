#include "stages/plan/rules.h"

#include <filesystem>
#include <map>
#include <fstream>
#include <sstream>

#include "common/error.h"
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
  std::filesystem::create_directories(std::filesystem::path(path).parent_path());
  const std::string temporary = path + ".tmp";
  {
    std::ofstream out(temporary, std::ios::binary);
    out << text;
    if (!out) throw DataError(Location::InFile(path), "cannot write");
  }
  std::filesystem::rename(temporary, path);
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

Plan MakePlan(const Manifest& manifest, const std::string& outputs_root) {
  Plan plan;
  plan.output_dir = outputs_root + "/" + manifest.name;
  std::map<std::string, std::vector<std::string>> synergies_by_style;
  // Archive-wide stages take the manifest's defaults (any trial's copy of them; overrides are per trial).
  const auto parameters_of_manifest = [&](const std::string& stage) {
    const auto found = manifest.trials.front().parameters.find(stage);
    return found == manifest.trials.front().parameters.end() ? nlohmann::json::object() : found->second;
  };
  for (const ManifestTrial& trial : manifest.trials) {
    const std::string trial_dir = plan.output_dir + "/trials/" + trial.id;
    const auto parameters_of = [&](const std::string& stage) {
      const auto found = trial.parameters.find(stage);
      return found == trial.parameters.end() ? nlohmann::json::object() : found->second;
    };
    PlannedJob ingest;
    ingest.stage = "ingest";
    ingest.trial = trial.id;
    ingest.output = trial_dir + "/markers.h5";
    ingest.inputs = {trial.path};
    ingest.stamp = plan.output_dir + "/params/" + trial.id + ".ingest.json";
    ingest.stamp_text = CanonicalJson(parameters_of("ingest")) + "\n";
    ingest.command = "$(SYN_BIN)/syn-ingest " + MakeEscaped(ShellWord(trial.path)) + " -o $@" +
                     MakeEscaped(FlagsFor(parameters_of("ingest")));
    const std::string markers = ingest.output;
    plan.jobs.push_back(std::move(ingest));

    if (manifest.model.empty() || manifest.robot_map.empty() || manifest.markerset.empty()) continue;
    PlannedJob retarget;
    retarget.stage = "retarget";
    retarget.trial = trial.id;
    retarget.output = trial_dir + "/motion.h5";
    retarget.inputs = {markers, manifest.model, manifest.robot_map, manifest.markerset};
    retarget.stamp = plan.output_dir + "/params/" + trial.id + ".retarget.json";
    retarget.stamp_text = CanonicalJson(parameters_of("retarget")) + "\n";
    retarget.command = "$(SYN_BIN)/syn-retarget " + markers + " -o $@ --model " + MakeEscaped(ShellWord(manifest.model)) +
                       " --robot-map " + MakeEscaped(ShellWord(manifest.robot_map)) + " --markerset " +
                       MakeEscaped(ShellWord(manifest.markerset)) + MakeEscaped(FlagsFor(parameters_of("retarget")));
    const std::string motion = retarget.output;
    plan.jobs.push_back(std::move(retarget));

    PlannedJob segment;
    segment.stage = "segment";
    segment.trial = trial.id;
    segment.output = trial_dir + "/segments.h5";
    segment.inputs = {motion, manifest.model};
    segment.stamp = plan.output_dir + "/params/" + trial.id + ".segment.json";
    segment.stamp_text = CanonicalJson(parameters_of("segment")) + "\n";
    segment.command = "$(SYN_BIN)/syn-segment " + motion + " -o $@ --model " + MakeEscaped(ShellWord(manifest.model)) +
                      MakeEscaped(FlagsFor(parameters_of("segment")));
    const std::string segments = segment.output;
    plan.jobs.push_back(std::move(segment));

    PlannedJob synergies;
    synergies.stage = "synergies";
    synergies.trial = trial.id;
    synergies.output = trial_dir + "/synergies.h5";
    synergies.inputs = {motion, segments};
    nlohmann::json synergy_parameters = parameters_of("synergies");
    synergy_parameters["subject"] = trial.subject;
    synergy_parameters["trial"] = trial.id;
    synergy_parameters["style"] = trial.style;
    synergy_parameters["motion_class"] = trial.motion_class;
    synergies.stamp = plan.output_dir + "/params/" + trial.id + ".synergies.json";
    synergies.stamp_text = CanonicalJson(synergy_parameters) + "\n";
    synergies.command = "$(SYN_BIN)/syn-synergies " + motion + " " + segments + " -o $@" +
                        MakeEscaped(FlagsFor(synergy_parameters));
    synergies_by_style[trial.style].push_back(synergies.output);
    plan.jobs.push_back(std::move(synergies));
  }
  // Summary tables over every trial.
  std::vector<std::string> all_synergies;
  for (const ManifestTrial& trial : manifest.trials) {
    if (!manifest.model.empty()) all_synergies.push_back(plan.output_dir + "/trials/" + trial.id + "/synergies.h5");
  }
  for (const char* table : {"trials", "segments"}) {
    if (all_synergies.empty()) break;
    PlannedJob summary;
    summary.stage = "summary";
    summary.trial = table;
    summary.output = plan.output_dir + "/summary/" + table + ".csv";
    summary.inputs = all_synergies;
    summary.stamp = plan.output_dir + "/params/summary." + table + ".json";
    summary.stamp_text = "{}\n";
    std::string command = "$(SYN_BIN)/syn-summary";
    for (const std::string& file : all_synergies) command += " " + file;
    summary.command = command + " --table " + table + " -o $@";
    plan.jobs.push_back(std::move(summary));
  }
  // One library per style, rebuilt when any of its trials' synergies change.
  for (const auto& [style, files] : synergies_by_style) {
    PlannedJob library;
    library.stage = "library";
    library.trial = style;
    library.output = plan.output_dir + "/library/" + style + ".h5";
    library.inputs = files;
    library.stamp = plan.output_dir + "/params/library." + style + ".json";
    library.stamp_text = CanonicalJson(parameters_of_manifest("library")) + "\n";
    std::string command = "$(SYN_BIN)/syn-library";
    for (const std::string& file : files) command += " " + file;
    library.command = command + " -o $@ --style " + MakeEscaped(ShellWord(style)) +
                      MakeEscaped(FlagsFor(parameters_of_manifest("library")));
    plan.jobs.push_back(std::move(library));
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
          << "\t@$(syn_start); " << job.command << " 2> $@.log && $(call syn_done," << job.stage << "," << job.trial
          << ") || $(call syn_failed," << job.stage << "," << job.trial << ")\n\n";
  }
  WriteIfChanged(rules_path, rules.str());
  return rewritten;
}

}  // namespace syn
