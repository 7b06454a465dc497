#include "stages/retarget/marker_set.h"

#include <algorithm>
#include <map>
#include <set>

#include <toml++/toml.h>

#include "common/error.h"
#include "common/file_bytes.h"

namespace syn {
namespace {

int LineOf(const toml::node& node) { return static_cast<int>(node.source().begin.line); }

[[noreturn]] void Fail(const std::string& file, int line, const std::string& message) {
  throw DataError(Location::AtLine(file, line), message);
}

PointChoice ParseChoice(const toml::node& node, const std::string& file) {
  const auto* text = node.as_string();
  if (!text || text->get().empty()) Fail(file, LineOf(node), "expected a point name such as \"LASI|LFWT\"");
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
    if (name.empty()) Fail(file, LineOf(node), "empty alternative in \"" + text->get() + "\"");
  }
  return choice;
}

std::vector<PointChoice> ParseChoices(const toml::node& node, const std::string& file, const char* key) {
  const auto* list = node.as_array();
  if (!list || list->empty()) Fail(file, LineOf(node), std::string("'") + key + "' must be a non-empty list of point names");
  std::vector<PointChoice> choices;
  for (const toml::node& element : *list) choices.push_back(ParseChoice(element, file));
  return choices;
}

AxisDefinition ParseAxis(char axis, const toml::node& node, const std::string& file) {
  const auto* table = node.as_table();
  if (!table) Fail(file, LineOf(node), std::string("axis '") + axis + "' must be { from = [...], to = [...] }");
  AxisDefinition definition;
  definition.axis = axis;
  for (const auto& [key, value] : *table) {
    if (key == "from") {
      definition.from = ParseChoices(value, file, "from");
    } else if (key == "to") {
      definition.to = ParseChoices(value, file, "to");
    } else {
      Fail(file, LineOf(value), "unknown key '" + std::string(key.str()) + "' in axis (expected from, to)");
    }
  }
  if (definition.from.empty() || definition.to.empty()) {
    Fail(file, LineOf(node), std::string("axis '") + axis + "' needs both 'from' and 'to'");
  }
  return definition;
}

LandmarkDefinition ParseLandmark(const toml::table& table, int line, const std::string& file) {
  LandmarkDefinition landmark;
  landmark.line = line;
  std::string primary, secondary;
  std::map<char, AxisDefinition> axes;
  for (const auto& [key, value] : table) {
    const std::string name(key.str());
    if (name == "name") {
      const auto* text = value.as_string();
      if (!text) Fail(file, LineOf(value), "'name' must be a string");
      landmark.name = text->get();
    } else if (name == "body") {
      landmark.body = ParseChoice(value, file);
    } else if (name == "origin") {
      landmark.origin = ParseChoices(value, file, "origin");
    } else if (name == "x" || name == "y" || name == "z") {
      axes[name[0]] = ParseAxis(name[0], value, file);
    } else if (name == "primary") {
      const auto* text = value.as_string();
      if (!text || text->get().size() != 1 || std::string("xyz").find(text->get()[0]) == std::string::npos) {
        Fail(file, LineOf(value), "'primary' must be \"x\", \"y\" or \"z\"");
      }
      primary = text->get();
    } else {
      Fail(file, LineOf(value), "unknown key '" + name + "' (expected name, body, origin, x, y, z, primary)");
    }
  }
  if (std::find_if(kLandmarkNames.begin(), kLandmarkNames.end(),
                   [&](const char* known) { return landmark.name == known; }) == kLandmarkNames.end()) {
    std::string known;
    for (const char* name : kLandmarkNames) known += std::string(known.empty() ? "" : ", ") + name;
    Fail(file, line, "unknown landmark '" + landmark.name + "'; expected one of " + known);
  }
  if (!landmark.body.empty()) {
    if (!landmark.origin.empty() || !axes.empty()) {
      Fail(file, line, "landmark '" + landmark.name + "' gives both a body and points; use one");
    }
    return landmark;
  }
  if (landmark.origin.empty()) Fail(file, line, "landmark '" + landmark.name + "' needs 'body' or 'origin'");
  if (axes.size() == 1 || axes.size() == 3) {
    Fail(file, line, "landmark '" + landmark.name + "' needs exactly two axes (or none for position only)");
  }
  if (axes.size() == 2) {
    if (primary.empty()) Fail(file, line, "landmark '" + landmark.name + "' must say which axis is 'primary'");
    if (!axes.count(primary[0])) Fail(file, line, "primary axis '" + primary + "' is not one of the two given");
    landmark.axes.push_back(axes[primary[0]]);
    for (auto& [axis, definition] : axes) {
      if (axis != primary[0]) landmark.axes.push_back(definition);
    }
  }
  return landmark;
}

}  // namespace

MarkerSet ParseMarkerSet(const std::string& toml_text, const std::string& file_name) {
  toml::table root;
  try {
    root = toml::parse(toml_text, file_name);
  } catch (const toml::parse_error& error) {
    throw DataError(Location::AtLine(file_name, static_cast<int64_t>(error.source().begin.line)),
                    std::string(error.description()));
  }
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
      if (!list) Fail(file_name, LineOf(value), "'landmark' must be an array of tables ([[landmark]])");
      for (const toml::node& element : *list) {
        const auto* table = element.as_table();
        if (!table) Fail(file_name, LineOf(element), "expected a [[landmark]] table");
        LandmarkDefinition landmark = ParseLandmark(*table, LineOf(element), file_name);
        if (!seen.insert(landmark.name).second) {
          Fail(file_name, landmark.line, "landmark '" + landmark.name + "' is defined twice");
        }
        set.landmarks.push_back(std::move(landmark));
      }
    } else {
      Fail(file_name, LineOf(value), "unknown key '" + name + "' (expected name, description, [[landmark]])");
    }
  }
  if (set.name.empty()) Fail(file_name, 1, "the marker set needs a 'name'");
  if (set.landmarks.empty()) Fail(file_name, 1, "the marker set defines no [[landmark]]");
  return set;
}

MarkerSet LoadMarkerSet(const std::string& path) { return ParseMarkerSet(ReadFileText(path), path); }

}  // namespace syn
