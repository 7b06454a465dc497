#include "common/release_manifest.h"

#include <algorithm>
#include <sstream>

#include "common/error.h"
#include "common/file_bytes.h"
#include "common/toml_fields.h"

namespace syn {

const std::vector<ReleaseExportFormat>& ReleaseExportFormats() {
  // The names for the formats (robot-csv, lafan1-csv, beyondmimic-npz, mot) are accepted as
  // aliases of syn-export's own.
  static const std::vector<ReleaseExportFormat> formats = {
      {"robot-csv", "motion.robot.csv", ""},
      {"unitree-csv", "motion.unitree.csv", "lafan1-csv"},
      {"mjlab-npz", "motion.mjlab.npz", "beyondmimic-npz"},
      {"gmr-npz", "motion.gmr.npz", ""},
      {"mot", "motion.mot", ""},
      {"csv", "motion.csv", ""},
  };
  return formats;
}

const ReleaseExportFormat* FindReleaseExportFormat(const std::string& name) {
  for (const ReleaseExportFormat& format : ReleaseExportFormats()) {
    if (format.name == name) return &format;
    std::istringstream aliases(format.aliases);
    for (std::string alias; std::getline(aliases, alias, ',');) {
      if (alias == name) return &format;
    }
  }
  return nullptr;
}

bool IsReleaseManifestKey(const std::string& key) {
  return key == "licence" || key == "source" || key == kReleaseManifestTable;
}

std::vector<std::string> ReleaseManifest::licenceWarnings() const {
  std::vector<std::string> warnings;
  for (const ReleaseTrial& trial : trials) {
    if (!trial.licence.empty()) continue;
    warnings.push_back(Location::AtLine(path, trial.line).ToString() + ": trial '" + trial.id +
                       "' names no licence (neither the trial nor the manifest has 'licence'): the release "
                       "datasheet will say \"unknown\"");
  }
  if (!model.empty() && model_licence.empty()) {
    warnings.push_back(path + ": the robot model " + model +
                       " has no licence ([release] model_licence): the release datasheet will say \"unknown\"");
  }
  return warnings;
}

namespace {

void ReadReleaseTable(const TomlFields& fields, const toml::node& node, ReleaseManifest& manifest) {
  const toml::table& table = fields.table(node, kReleaseManifestTable);
  for (const auto& [key, value] : table) {
    const std::string name(key.str());
    if (name == "licence") {
      manifest.release_licence = fields.text(value, name);
    } else if (name == "citation") {
      manifest.citation = fields.text(value, name);
    } else if (name == "model_licence") {
      manifest.model_licence = fields.text(value, name);
    } else if (name == "model_source") {
      manifest.model_source = fields.text(value, name);
    } else if (name == "model_licence_file") {
      manifest.model_licence_file = fields.text(value, name);
    } else if (name == "exports") {
      const auto* list = value.as_array();
      if (!list) fields.fail(value, "'exports' must be a list of syn-export format names");
      for (const toml::node& element : *list) {
        const std::string format_name = fields.text(element, "exports");
        const ReleaseExportFormat* format = FindReleaseExportFormat(format_name);
        if (!format) {
          std::string known;
          for (const ReleaseExportFormat& each : ReleaseExportFormats()) {
            known += (known.empty() ? "" : ", ") + each.name + (each.aliases.empty() ? "" : " (" + each.aliases + ")");
          }
          fields.fail(element, "unknown export format '" + format_name + "' (known: " + known + ")");
        }
        if (std::find(manifest.exports.begin(), manifest.exports.end(), format->name) != manifest.exports.end()) {
          fields.fail(element, "export format '" + format->name + "' is listed twice");
        }
        manifest.exports.push_back(format->name);
      }
    } else {
      fields.fail(value, "unknown [release] key '" + name +
                             "' (expected licence, citation, exports, model_licence, model_source, model_licence_file)");
    }
  }
}

}  // namespace

ReleaseManifest ParseReleaseManifest(const std::string& toml_text, const std::string& path) {
  const TomlFields fields(path);
  const toml::table root = fields.parseText(toml_text);
  ReleaseManifest manifest;
  manifest.path = path;
  const auto text_of = [&](const toml::node& value, const std::string& key) { return fields.text(value, key); };
  for (const auto& [key, value] : root) {
    const std::string name(key.str());
    if (name == "name") manifest.name = text_of(value, name);
    else if (name == "version") manifest.version = text_of(value, name);
    else if (name == "description") manifest.description = text_of(value, name);
    else if (name == "root") manifest.root = text_of(value, name);
    else if (name == "model") manifest.model = text_of(value, name);
    else if (name == "robot_map") manifest.robot_map = text_of(value, name);
    else if (name == "licence") manifest.licence = text_of(value, name);
    else if (name == "source") manifest.source = text_of(value, name);
    else if (name == kReleaseManifestTable) ReadReleaseTable(fields, value, manifest);
  }
  if (manifest.name.empty()) fields.fail(1, "the manifest needs a 'name'");
  const toml::array* trials = root["trial"].as_array();
  if (!trials) fields.fail(1, "the manifest lists no [[trial]]");
  for (const toml::node& element : *trials) {
    const auto* table = element.as_table();
    if (!table) fields.fail(element, "expected a [[trial]] table");
    ReleaseTrial trial;
    trial.line = LineOf(element);
    std::string style;
    for (const auto& [key, value] : *table) {
      const std::string name(key.str());
      if (name == "id") trial.id = text_of(value, name);
      else if (name == "subject") trial.subject = value.is_integer() ? std::to_string(value.as_integer()->get()) : text_of(value, name);
      else if (name == "motion_class") trial.motion_class = text_of(value, name);
      else if (name == "style") style = text_of(value, name);
      else if (name == "licence") trial.licence = text_of(value, name);
      else if (name == "source") trial.source = text_of(value, name);
    }
    if (trial.id.empty()) fields.fail(trial.line, "a trial needs an 'id'");
    // syn-plan's rule (stages/plan/manifest.cpp): the style defaults to the motion class.
    trial.style = !style.empty() ? style : !trial.motion_class.empty() ? trial.motion_class : "default";
    if (trial.licence.empty()) trial.licence = manifest.licence;
    if (trial.source.empty()) trial.source = manifest.source;
    manifest.trials.push_back(std::move(trial));
  }
  return manifest;
}

ReleaseManifest ReadReleaseManifest(const std::string& path) {
  return ParseReleaseManifest(ReadFileText(path), path);
}

}  // namespace syn
