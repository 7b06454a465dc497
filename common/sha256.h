// SHA-256 digests as lowercase hex, for the `inputs` provenance attribute of
// every intermediate file and for model identity.
#pragma once

#include <cstddef>
#include <string>

namespace syn {

[[nodiscard]] std::string Sha256Hex(const void* data, size_t size);

// Digest of a file's bytes, streamed. Throws DataError if it cannot be read.
[[nodiscard]] std::string Sha256OfFile(const std::string& path);

}  // namespace syn
