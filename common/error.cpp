#include "common/error.h"

#include "common/text_encoding.h"

namespace syn {

std::string Location::ToString() const {
  if (line >= 0) return file + ":" + std::to_string(line);
  if (frame >= 0) return file + ": frame " + std::to_string(frame);
  if (byte_offset >= 0) return file + ": byte offset " + std::to_string(byte_offset);
  return file;
}

DataError::DataError(Location where, const std::string& message)
    // Messages quote text from files (labels, header fields): non-printable bytes are escaped as \xNN.
    : std::runtime_error(Printable(where.ToString() + ": " + message)),
      where_(std::move(where)),
      message_(Printable(message)) {}

}  // namespace syn
