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

// Test hook for the kill test (tests/plan/incremental_make_test.cpp): when the
// environment variable SYN_TEST_PAUSE_BEFORE_RENAME is set and `path` ends with
// its value, prints "syn: test hook: paused before renaming <temporary>" to
// stderr and sleeps (up to 120 s) with the complete temporary file on disk, so
// a test can kill the writer at the worst moment. Inert when the variable is
// unset, which it always is outside that test. Both atomic writers call it
// just before their rename.
void PauseBeforeRenameIfRequested(const std::string& path, const std::string& temporary);

}  // namespace syn
