#include "common/error.h"

namespace syn {

std::string Location::ToString() const {
  if (line >= 0) return file + ":" + std::to_string(line);
  if (frame >= 0) return file + ": frame " + std::to_string(frame);
  if (byte_offset >= 0) return file + ": byte offset " + std::to_string(byte_offset);
  return file;
}

DataError::DataError(Location where, const std::string& message)
    : std::runtime_error(where.ToString() + ": " + message),
      where_(std::move(where)),
      message_(message) {}

}  // namespace syn
