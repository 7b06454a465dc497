// Line and field splitting for the text capture formats (TRC, Motive CSV).
#pragma once

#include <cstdint>
#include <string>
#include <string_view>
#include <vector>

namespace syn {

// Hands out the lines of a text one by one, without their "\n" or "\r\n",
// counting them from 1 for error messages.
class LineReader {
 public:
  explicit LineReader(std::string_view text) : text_(text) {}
  bool next(std::string_view* line);
  int64_t lineNumber() const { return line_number_; }  // of the line last returned

 private:
  std::string_view text_;
  size_t position_ = 0;
  int64_t line_number_ = 0;
};

// Splits on `delimiter`, keeping empty fields ("a,,b" -> "a", "", "b").
void SplitFields(std::string_view line, char delimiter, std::vector<std::string_view>& fields);
// Splits a CSV line on commas outside double quotes, dropping the quotes ("a,\"b, c\",d" -> a | b, c | d).
[[nodiscard]] std::vector<std::string> SplitQuotedCsv(std::string_view line);
// Splits on runs of spaces and tabs (no empty fields).
void SplitWhitespace(std::string_view line, std::vector<std::string_view>& fields);

std::string_view Trim(std::string_view text);

enum class FieldValue { kNumber, kEmpty, kInvalid };

// A decimal number (E-notation, leading '+' allowed) or NaN in any case
// ("NaN", "nan", "NAN", "Nan"); surrounding spaces ignored. Empty or NaN
// fields give *value = NaN.
FieldValue ParseField(std::string_view field, double* value);

}  // namespace syn
