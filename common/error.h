// Errors that name where the bad input is.
//
// Every failure a user can cause (bad file, bad parameter) is reported as a
// `DataError` carrying the file and a location inside it: a line, a frame or a
// byte offset. The stage's main() translates it once into "file:line: message"
// and exit code 1 (see common/stage_main.h). Usage mistakes are `UsageError`,
// exit code 2. Anything else escaping a stage is a bug and is reported as one.
#pragma once

#include <cstdint>
#include <stdexcept>
#include <string>

namespace syn {

// Where in a file a problem was found. At most one of the fields is usually set.
struct Location {
  std::string file;
  int64_t line = -1;         // 1-based text line
  int64_t frame = -1;        // 0-based sample frame
  int64_t byte_offset = -1;  // 0-based offset into a binary file

  static Location AtLine(std::string file, int64_t line) { return {std::move(file), line, -1, -1}; }
  static Location AtFrame(std::string file, int64_t frame) { return {std::move(file), -1, frame, -1}; }
  static Location AtByte(std::string file, int64_t offset) { return {std::move(file), -1, -1, offset}; }
  static Location InFile(std::string file) { return {std::move(file), -1, -1, -1}; }

  // "file:12", "file: frame 40", "file: byte offset 512", or "file".
  std::string ToString() const;
};

// Bad input data or a failed operation on it: exit code 1.
class DataError : public std::runtime_error {
 public:
  DataError(Location where, const std::string& message);
  const Location& where() const { return where_; }
  const std::string& message() const { return message_; }

 private:
  Location where_;
  std::string message_;
};

// The command line itself is wrong: exit code 2.
class UsageError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace syn
