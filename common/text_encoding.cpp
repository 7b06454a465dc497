#include "common/text_encoding.h"

#include <cstdint>

namespace syn {
namespace {

// Length of the valid UTF-8 sequence starting at text[i], or 0 if none (overlong forms, surrogates and
// code points above U+10FFFF are invalid, as RFC 3629 says).
size_t Utf8SequenceLength(std::string_view text, size_t i) {
  const auto byte = [&](size_t k) { return static_cast<uint8_t>(text[k]); };
  const uint8_t lead = byte(i);
  if (lead < 0x80) return 1;
  size_t length = 0;
  uint32_t minimum = 0, code = 0;
  if ((lead & 0xE0) == 0xC0) length = 2, minimum = 0x80, code = lead & 0x1F;
  else if ((lead & 0xF0) == 0xE0) length = 3, minimum = 0x800, code = lead & 0x0F;
  else if ((lead & 0xF8) == 0xF0) length = 4, minimum = 0x10000, code = lead & 0x07;
  else return 0;
  if (i + length > text.size()) return 0;
  for (size_t k = 1; k < length; ++k) {
    if ((byte(i + k) & 0xC0) != 0x80) return 0;
    code = (code << 6) | (byte(i + k) & 0x3F);
  }
  if (code < minimum || code > 0x10FFFF || (code >= 0xD800 && code <= 0xDFFF)) return 0;
  return length;
}

void AppendEscaped(std::string& out, uint8_t byte) {
  static const char* kHex = "0123456789ABCDEF";
  out += "\\x";
  out += kHex[byte >> 4];
  out += kHex[byte & 0xF];
}

}  // namespace

bool IsValidUtf8(std::string_view text) {
  for (size_t i = 0; i < text.size();) {
    const size_t length = Utf8SequenceLength(text, i);
    if (length == 0) return false;
    i += length;
  }
  return true;
}

std::string ToUtf8(std::string_view text) {
  if (IsValidUtf8(text)) return std::string(text);
  std::string out;
  out.reserve(text.size() + 8);
  for (size_t i = 0; i < text.size();) {
    const size_t length = Utf8SequenceLength(text, i);
    if (length > 0) {
      out.append(text.substr(i, length));
      i += length;
      continue;
    }
    const uint8_t byte = static_cast<uint8_t>(text[i++]);
    if (byte >= 0xA0) {  // Latin-1 U+00A0..U+00FF as two UTF-8 bytes
      out += static_cast<char>(0xC0 | (byte >> 6));
      out += static_cast<char>(0x80 | (byte & 0x3F));
    } else {
      AppendEscaped(out, byte);
    }
  }
  return out;
}

std::string Printable(std::string_view text) {
  const std::string utf8 = ToUtf8(text);
  std::string out;
  out.reserve(utf8.size());
  for (char c : utf8) {
    const auto byte = static_cast<uint8_t>(c);
    if ((byte < 0x20 && c != '\t' && c != '\n') || byte == 0x7F) AppendEscaped(out, byte);
    else out += c;
  }
  return out;
}

void MakeJsonUtf8(nlohmann::json& value) {
  if (value.is_string()) {
    std::string& text = value.get_ref<std::string&>();
    if (!IsValidUtf8(text)) text = ToUtf8(text);
  } else if (value.is_array()) {
    for (nlohmann::json& element : value) MakeJsonUtf8(element);
  } else if (value.is_object()) {
    bool keys_valid = true;
    for (auto it = value.begin(); it != value.end(); ++it) keys_valid = keys_valid && IsValidUtf8(it.key());
    if (!keys_valid) {
      nlohmann::json rebuilt = nlohmann::json::object();
      for (auto it = value.begin(); it != value.end(); ++it) rebuilt[ToUtf8(it.key())] = it.value();
      value = std::move(rebuilt);
    }
    for (auto it = value.begin(); it != value.end(); ++it) MakeJsonUtf8(it.value());
  }
}

}  // namespace syn
