#include "stages/plan/manifest.h"

#include <algorithm>
#include <filesystem>
#include <set>

#include "common/error.h"
#include "common/toml_fields.h"

namespace syn {
namespace {

constexpr const char* kMappingKey = "mapping";

class ManifestParser {
 public:
  ManifestParser(std::string path, const std::vector<StageParameterNames>& stages) : fields_(std::move(path)), stages_(stages) {}

  const StageParameterNames* stage(const std::string& name) const {
    for (const StageParameterNames& stage : stages_) {
      if (stage.stage == name) return &stage;
    }
    return nullptr;
  }

  // The one stage that has a parameter of this name, or nullptr.
  const StageParameterNames* stageOwning(const std::string& parameter) const {
    const StageParameterNames* owner = nullptr;
    for (const StageParameterNames& stage : stages_) {
      if (std::find(stage.names.begin(), stage.names.end(), parameter) == stage.names.end()) continue;
      if (owner) return nullptr;  // ambiguous: must be written in a stage table
      owner = &stage;
    }
    return owner;
  }

  // `mapping` (in [retarget] or a trial): "kinematic" or "osc".
  std::string mapping(const toml::node& node) const {
    const std::string value = fields_.text(node, kMappingKey);
    if (value != "kinematic" && value != "osc") {
      fields_.fail(node, "mapping must be \"kinematic\" or \"osc\", got \"" + value + "\"");
    }
    return value;
  }

  nlohmann::json scalar(const toml::node& node, const std::string& key) const {
    if (const auto* value = node.as_string()) return value->get();
    if (const auto* value = node.as_integer()) return value->get();
    if (const auto* value = node.as_floating_point()) return value->get();
    if (const auto* value = node.as_boolean()) return value->get();
    fields_.fail(node, "parameter '" + key + "' must be a string, number or boolean");
  }

  void addParameters(const toml::node& node, const StageParameterNames& stage, nlohmann::json& into) const {
    const auto* table = node.as_table();
    if (!table) fields_.fail(node, "'" + stage.stage + "' must be a table of parameters");
    for (const auto& [key, value] : *table) {
      const std::string name(key.str());
      if (stage.stage == "retarget" && name == kMappingKey) {  // syn-plan's own: which route the motion takes
        into[name] = mapping(value);
        continue;
      }
      if (std::find(stage.names.begin(), stage.names.end(), name) == stage.names.end()) {
        std::string known;
        for (const std::string& parameter : stage.names) known += (known.empty() ? "" : ", ") + parameter;
        fields_.fail(value, "unknown " + stage.stage + " parameter '" + name + "' (known: " + known + ")");
      }
      into[name] = scalar(value, name);
    }
  }

  Manifest parse() {
    const toml::table root = fields_.parseFile();
    Manifest manifest;
    manifest.path = fields_.file();
    std::map<std::string, nlohmann::json> defaults;
    const toml::array* trials = nullptr;
    int trials_line = 1;
    for (const auto& [key, value] : root) {
      const std::string name(key.str());
      if (name == "name") {
        manifest.name = fields_.text(value, name);
        const bool ok = !manifest.name.empty() && std::all_of(manifest.name.begin(), manifest.name.end(), [](char c) {
          return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-';
        });
        if (!ok) fields_.fail(value, "'name' may hold only letters, digits, '_' and '-' (it names a folder)");
      } else if (name == "version") {
        manifest.version = fields_.text(value, name);
      } else if (name == "description") {
        manifest.description = fields_.text(value, name);
      } else if (name == "root") {
        manifest.root = fields_.text(value, name);
      } else if (name == "model") {
        manifest.model = fields_.text(value, name);
      } else if (name == "robot_map") {
        manifest.robot_map = fields_.text(value, name);
      } else if (name == "markerset") {
        manifest.markerset = fields_.text(value, name);
      } else if (IsReleaseManifestKey(name)) {
        // licence, source, [release]: read by ReadReleaseManifest (LoadManifest).
      } else if (name == "trial") {
        trials = value.as_array();
        trials_line = LineOf(value);
        if (!trials) fields_.fail(value, "'trial' must be written as [[trial]] tables");
      } else if (const StageParameterNames* stage_names = stage(name)) {
        addParameters(value, *stage_names, defaults[name]);
      } else {
        fields_.fail(value, "unknown key '" + name +
                                "' (expected name, version, description, root, model, robot_map, markerset, licence, "
                                "source, [release], a stage table, or [[trial]])");
      }
    }
    if (manifest.name.empty()) fields_.fail(1, "the manifest needs a 'name'");
    if (!trials || trials->empty()) fields_.fail(trials_line, "the manifest lists no [[trial]]");
    for (const std::string* file : {&manifest.model, &manifest.robot_map, &manifest.markerset}) {
      std::error_code unreadable;  // a name too long for the file system is as missing as an absent file
      if (!file->empty() && !std::filesystem::exists(*file, unreadable)) fields_.fail(1, "file not found: " + *file);
    }

    std::set<std::string> ids;
    for (const toml::node& element : *trials) {
      const auto* table = element.as_table();
      if (!table) fields_.fail(element, "expected a [[trial]] table");
      ManifestTrial trial;
      trial.line = LineOf(element);
      trial.parameters = defaults;
      for (const auto& [key, value] : *table) {
        const std::string name(key.str());
        if (name == "id") {
          trial.id = fields_.text(value, name);
        } else if (name == "subject") {
          trial.subject = value.is_integer() ? std::to_string(value.as_integer()->get()) : fields_.text(value, name);
        } else if (name == "file") {
          trial.file = fields_.text(value, name);
        } else if (name == "style") {
          trial.style = fields_.text(value, name);
        } else if (name == "motion_class") {
          trial.motion_class = fields_.text(value, name);
        } else if (name == "genre") {
          trial.genre = fields_.text(value, name);
        } else if (name == "licence" || name == "source") {
          static_cast<void>(fields_.text(value, name));  // checked here, read by ReadReleaseManifest
        } else if (name == kMappingKey) {
          trial.parameters["retarget"][kMappingKey] = mapping(value);
        } else if (const StageParameterNames* stage_names = stage(name)) {
          addParameters(value, *stage_names, trial.parameters[name]);
        } else if (const StageParameterNames* owner = stageOwning(name)) {
          trial.parameters[owner->stage][name] = scalar(value, name);
        } else {
          fields_.fail(value, "unknown trial key '" + name +
                                  "' (expected id, subject, file, style, motion_class, genre, licence, source, a stage "
                                  "table, or a parameter name of one stage)");
        }
      }
      // The mapping chooses the plan's route; it is no parameter of syn-retarget.
      if (auto found = trial.parameters.find("retarget"); found != trial.parameters.end() && found->second.contains(kMappingKey)) {
        trial.mapping = found->second[kMappingKey].get<std::string>();
        found->second.erase(kMappingKey);
      }
      if (trial.id.empty()) fields_.fail(trial.line, "a trial needs an 'id'");
      const bool id_ok = std::all_of(trial.id.begin(), trial.id.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
      });
      if (!id_ok) fields_.fail(trial.line, "trial id '" + trial.id + "' may hold only letters, digits, '_', '-' and '.'");
      if (!ids.insert(trial.id).second) fields_.fail(trial.line, "duplicate trial id '" + trial.id + "'");
      if (trial.file.empty()) fields_.fail(trial.line, "trial '" + trial.id + "' needs a 'file'");
      if (trial.style.empty()) trial.style = trial.motion_class.empty() ? "default" : trial.motion_class;
      const bool style_ok = std::all_of(trial.style.begin(), trial.style.end(), [](char c) {
        return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
      });
      if (!style_ok) fields_.fail(trial.line, "style '" + trial.style + "' may hold only letters, digits, '_', '-' and '.' (it names a file)");
      manifest.trials.push_back(std::move(trial));
    }
    return manifest;
  }

 private:
  TomlFields fields_;
  const std::vector<StageParameterNames>& stages_;
};

}  // namespace

Manifest LoadManifest(const std::string& path, const std::string& dataset_root,
                      const std::vector<StageParameterNames>& stages) {
  Manifest manifest = ManifestParser(path, stages).parse();
  manifest.release = ReadReleaseManifest(path);
  if (!dataset_root.empty()) manifest.root = dataset_root;
  for (ManifestTrial& trial : manifest.trials) {
    trial.path = manifest.root.empty() ? trial.file : manifest.root + "/" + trial.file;
    std::error_code unreadable;
    if (!std::filesystem::is_regular_file(trial.path, unreadable)) {
      throw DataError(Location::AtLine(path, trial.line),
                      "trial '" + trial.id + "': capture file not found: " + trial.path +
                          (dataset_root.empty() ? " (set DATASET_ROOT= if the archive lives elsewhere)" : ""));
    }
  }
  return manifest;
}

}  // namespace syn
