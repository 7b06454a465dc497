#include "common/toml_fields.h"

#include "common/error.h"
#include "common/file_bytes.h"

namespace syn {

int LineOf(const toml::node& node) { return static_cast<int>(node.source().begin.line); }

toml::table TomlFields::parseFile() const { return parseText(ReadFileText(file_)); }

toml::table TomlFields::parseText(const std::string& toml_text) const {
  try {
    return toml::parse(toml_text, file_);
  } catch (const toml::parse_error& error) {
    fail(static_cast<int>(error.source().begin.line), std::string(error.description()));
  }
}

void TomlFields::fail(int line, const std::string& message) const {
  throw DataError(Location::AtLine(file_, line), message);
}

std::string TomlFields::text(const toml::node& node, const std::string& key) const {
  const auto* value = node.as_string();
  if (!value) fail(node, "'" + key + "' must be a string");
  return value->get();
}

double TomlFields::number(const toml::node& node, const std::string& key) const {
  if (const auto* value = node.as_floating_point()) return value->get();
  if (const auto* value = node.as_integer()) return static_cast<double>(value->get());
  fail(node, "'" + key + "' must be a number");
}

int64_t TomlFields::integer(const toml::node& node, const std::string& key) const {
  const auto* value = node.as_integer();
  if (!value) fail(node, "'" + key + "' must be an integer");
  return value->get();
}

std::vector<double> TomlFields::numbers(const toml::node& node, const std::string& key) const {
  const auto* array = node.as_array();
  if (!array) fail(node, "'" + key + "' must be an array of numbers");
  std::vector<double> values;
  for (const toml::node& element : *array) values.push_back(number(element, key));
  return values;
}

const toml::table& TomlFields::table(const toml::node& node, const std::string& key) const {
  const auto* value = node.as_table();
  if (!value) fail(node, "'" + key + "' must be a table");
  return *value;
}

}  // namespace syn
