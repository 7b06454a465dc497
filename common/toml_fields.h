// Typed reads from a parsed TOML file with errors located at `file:line`:
// the one place manifests, robot maps, marker sets and compose scripts turn
// TOML nodes into values. Include only where toml++ is already needed (it is
// a heavy header).
#pragma once

#include <string>
#include <vector>

#include <toml++/toml.h>

namespace syn {

[[nodiscard]] int LineOf(const toml::node& node);

class TomlFields {
 public:
  explicit TomlFields(std::string file) : file_(std::move(file)) {}
  const std::string& file() const { return file_; }

  // Reads and parses the file; a syntax error is a DataError at its line.
  [[nodiscard]] toml::table parseFile() const;
  // Parses `toml_text` as the content of the file (tests and fuzzers parse from memory).
  [[nodiscard]] toml::table parseText(const std::string& toml_text) const;

  [[noreturn]] void fail(int line, const std::string& message) const;
  [[noreturn]] void fail(const toml::node& node, const std::string& message) const { fail(LineOf(node), message); }

  [[nodiscard]] std::string text(const toml::node& node, const std::string& key) const;
  [[nodiscard]] double number(const toml::node& node, const std::string& key) const;
  [[nodiscard]] int64_t integer(const toml::node& node, const std::string& key) const;
  [[nodiscard]] std::vector<double> numbers(const toml::node& node, const std::string& key) const;
  [[nodiscard]] const toml::table& table(const toml::node& node, const std::string& key) const;

 private:
  std::string file_;
};

}  // namespace syn
