// Whole-file reads for the format readers: one read into memory, then parse
// from the buffer, so the same parser serves files, tests and fuzzers.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace syn {

// Reads the whole file. Throws DataError naming the file if it cannot be
// opened or read.
[[nodiscard]] std::vector<uint8_t> ReadFileBytes(const std::string& path);

// Same, as text (bytes unchanged, no newline translation).
[[nodiscard]] std::string ReadFileText(const std::string& path);

// Writes `text` to a temporary name beside `path` and renames it, so a reader
// (or make, after a kill) never sees a half-written file. Throws DataError.
void WriteFileAtomically(const std::string& path, const std::string& text);

}  // namespace syn
