#include "common/marker_set.h"

#include <algorithm>
#include <map>
#include <set>

#include "common/error.h"
#include "common/file_bytes.h"
#include "common/toml_fields.h"

namespace syn {
namespace {

PointChoice ParseChoice(const toml::node& node, const TomlFields& fields) {
  const auto* text = node.as_string();
  if (!text || text->get().empty()) fields.fail(node, "expected a point name such as \"LASI|LFWT\"");
  PointChoice choice;
  std::string current;
  for (char c : text->get()) {
    if (c == '|') {
      choice.push_back(current);
      current.clear();
    } else {
      current += c;
    }
  }
  choice.push_back(current);
  for (const std::string& name : choice) {
    if (name.empty()) fields.fail(node, "empty alternative in \"" + text->get() + "\"");
  }
  return choice;
}

std::vector<PointChoice> ParseChoices(const toml::node& node, const TomlFields& fields, const char* key) {
  const auto* list = node.as_array();
  if (!list || list->empty()) fields.fail(node, std::string("'") + key + "' must be a non-empty list of point names");
  std::vector<PointChoice> choices;
  for (const toml::node& element : *list) choices.push_back(ParseChoice(element, fields));
  return choices;
}

AxisDefinition ParseAxis(char axis, const toml::node& node, const TomlFields& fields) {
  const auto* table = node.as_table();
  if (!table) fields.fail(node, std::string("axis '") + axis + "' must be { from = [...], to = [...] }");
  AxisDefinition definition;
  definition.axis = axis;
  for (const auto& [key, value] : *table) {
    if (key == "from") {
      definition.from = ParseChoices(value, fields, "from");
    } else if (key == "to") {
      definition.to = ParseChoices(value, fields, "to");
    } else {
      fields.fail(value, "unknown key '" + std::string(key.str()) + "' in axis (expected from, to)");
    }
  }
  if (definition.from.empty() || definition.to.empty()) {
    fields.fail(node, std::string("axis '") + axis + "' needs both 'from' and 'to'");
  }
  return definition;
}

LandmarkDefinition ParseLandmark(const toml::table& table, int line, const TomlFields& fields) {
  LandmarkDefinition landmark;
  landmark.line = line;
  std::string primary, secondary;
  std::map<char, AxisDefinition> axes;
  for (const auto& [key, value] : table) {
    const std::string name(key.str());
    if (name == "name") {
      const auto* text = value.as_string();
      if (!text) fields.fail(value, "'name' must be a string");
      landmark.name = text->get();
    } else if (name == "body") {
      landmark.body = ParseChoice(value, fields);
    } else if (name == "origin") {
      landmark.origin = ParseChoices(value, fields, "origin");
    } else if (name == "x" || name == "y" || name == "z") {
      axes[name[0]] = ParseAxis(name[0], value, fields);
    } else if (name == "primary") {
      const auto* text = value.as_string();
      if (!text || text->get().size() != 1 || std::string("xyz").find(text->get()[0]) == std::string::npos) {
        fields.fail(value, "'primary' must be \"x\", \"y\" or \"z\"");
      }
      primary = text->get();
    } else {
      fields.fail(value, "unknown key '" + name + "' (expected name, body, origin, x, y, z, primary)");
    }
  }
  if (std::find_if(kLandmarkNames.begin(), kLandmarkNames.end(),
                   [&](const char* known) { return landmark.name == known; }) == kLandmarkNames.end()) {
    std::string known;
    for (const char* name : kLandmarkNames) known += std::string(known.empty() ? "" : ", ") + name;
    fields.fail(line, "unknown landmark '" + landmark.name + "'; expected one of " + known);
  }
  if (!landmark.body.empty()) {
    if (!landmark.origin.empty() || !axes.empty()) {
      fields.fail(line, "landmark '" + landmark.name + "' gives both a body and points; use one");
    }
    return landmark;
  }
  if (landmark.origin.empty()) fields.fail(line, "landmark '" + landmark.name + "' needs 'body' or 'origin'");
  if (axes.size() == 1 || axes.size() == 3) {
    fields.fail(line, "landmark '" + landmark.name + "' needs exactly two axes (or none for position only)");
  }
  if (axes.size() == 2) {
    if (primary.empty()) fields.fail(line, "landmark '" + landmark.name + "' must say which axis is 'primary'");
    if (!axes.count(primary[0])) fields.fail(line, "primary axis '" + primary + "' is not one of the two given");
    landmark.axes.push_back(axes[primary[0]]);
    for (auto& [axis, definition] : axes) {
      if (axis != primary[0]) landmark.axes.push_back(definition);
    }
  }
  return landmark;
}

}  // namespace

MarkerSet ParseMarkerSet(const std::string& toml_text, const std::string& file_name) {
  const TomlFields fields(file_name);
  const toml::table root = fields.parseText(toml_text);
  MarkerSet set;
  set.file = file_name;
  std::set<std::string> seen;
  for (const auto& [key, value] : root) {
    const std::string name(key.str());
    if (name == "name") {
      set.name = value.value_or(std::string());
    } else if (name == "description") {
      set.description = value.value_or(std::string());
    } else if (name == "landmark") {
      const auto* list = value.as_array();
      if (!list) fields.fail(value, "'landmark' must be an array of tables ([[landmark]])");
      for (const toml::node& element : *list) {
        const auto* table = element.as_table();
        if (!table) fields.fail(element, "expected a [[landmark]] table");
        LandmarkDefinition landmark = ParseLandmark(*table, LineOf(element), fields);
        if (!seen.insert(landmark.name).second) {
          fields.fail(landmark.line, "landmark '" + landmark.name + "' is defined twice");
        }
        set.landmarks.push_back(std::move(landmark));
      }
    } else {
      fields.fail(value, "unknown key '" + name + "' (expected name, description, [[landmark]])");
    }
  }
  if (set.name.empty()) fields.fail(1, "the marker set needs a 'name'");
  if (set.landmarks.empty()) fields.fail(1, "the marker set defines no [[landmark]]");
  return set;
}

MarkerSet LoadMarkerSet(const std::string& path) { return ParseMarkerSet(ReadFileText(path), path); }

}  // namespace syn
