#include "stages/ingest/text_fields.h"

#include <charconv>
#include <cmath>

namespace syn {

bool LineReader::next(std::string_view* line) {
  if (position_ >= text_.size()) return false;
  size_t end = text_.find('\n', position_);
  if (end == std::string_view::npos) end = text_.size();
  std::string_view found = text_.substr(position_, end - position_);
  if (!found.empty() && found.back() == '\r') found.remove_suffix(1);
  position_ = end + 1;
  ++line_number_;
  *line = found;
  return true;
}

void SplitFields(std::string_view line, char delimiter, std::vector<std::string_view>& fields) {
  fields.clear();
  size_t start = 0;
  while (true) {
    const size_t end = line.find(delimiter, start);
    if (end == std::string_view::npos) {
      fields.push_back(line.substr(start));
      return;
    }
    fields.push_back(line.substr(start, end - start));
    start = end + 1;
  }
}

void SplitWhitespace(std::string_view line, std::vector<std::string_view>& fields) {
  fields.clear();
  size_t position = 0;
  while (position < line.size()) {
    while (position < line.size() && (line[position] == ' ' || line[position] == '\t')) ++position;
    if (position >= line.size()) break;
    const size_t start = position;
    while (position < line.size() && line[position] != ' ' && line[position] != '\t') ++position;
    fields.push_back(line.substr(start, position - start));
  }
}

std::string_view Trim(std::string_view text) {
  while (!text.empty() && (text.front() == ' ' || text.front() == '\t' || text.front() == '\r')) text.remove_prefix(1);
  while (!text.empty() && (text.back() == ' ' || text.back() == '\t' || text.back() == '\r')) text.remove_suffix(1);
  return text;
}

FieldValue ParseField(std::string_view field, double* value) {
  field = Trim(field);
  if (field.empty()) {
    *value = std::nan("");
    return FieldValue::kEmpty;
  }
  if (field.front() == '+') field.remove_prefix(1);
  const auto [end, error] = std::from_chars(field.data(), field.data() + field.size(), *value);
  if (error != std::errc() || end != field.data() + field.size()) return FieldValue::kInvalid;
  if (std::isinf(*value)) return FieldValue::kInvalid;
  return FieldValue::kNumber;
}

std::vector<std::string> SplitQuotedCsv(std::string_view line) {
  std::vector<std::string> cells(1);
  bool quoted = false;
  for (char c : line) {
    if (c == '"') quoted = !quoted;
    else if (c == ',' && !quoted) cells.emplace_back();
    else cells.back() += c;
  }
  return cells;
}

}  // namespace syn
