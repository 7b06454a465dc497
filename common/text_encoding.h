// Text that came from a file, made safe to store and to print.
//
// Capture files carry labels, units, descriptions and header fields in whatever encoding the writer
// used (Latin-1 from older Windows tools, raw bytes from damaged files). JSON and HDF5 attributes need
// UTF-8, and messages must not put control bytes on a terminal. One rule everywhere:
//
//   ToUtf8: valid UTF-8 stays as it is. Every byte that is not part of a valid UTF-8 sequence is read
//   as Latin-1 when it is a printable Latin-1 character (0xA0-0xFF: "\xE9" -> "é"); any other such
//   byte (0x80-0x9F, the C1 controls) becomes the four characters \xNN (uppercase hex).
//
//   Printable: ToUtf8, then every control character (0x00-0x1F except tab and newline, and 0x7F) also
//   becomes \xNN.
//   For messages and warnings.
#pragma once

#include <string>
#include <string_view>

#include <nlohmann/json.hpp>

namespace syn {

[[nodiscard]] bool IsValidUtf8(std::string_view text);
[[nodiscard]] std::string ToUtf8(std::string_view text);
[[nodiscard]] std::string Printable(std::string_view text);

// Applies ToUtf8 to every string and every object key inside `value` (in place).
void MakeJsonUtf8(nlohmann::json& value);

}  // namespace syn
