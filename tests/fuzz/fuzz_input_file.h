// For fuzz targets whose reader takes a path (whole-capture ingest, manifests, compose scripts, robot CSV,
// HDF5 intermediates): writes the input's bytes to one file per fuzzer process, under the temp directory,
// and returns its path. The file is rewritten for every input; nothing else is kept.
#pragma once

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <filesystem>
#include <string>

namespace syn::fuzzing {

inline std::string WriteFuzzInput(const uint8_t* data, size_t size, const std::string& file_name) {
  static const std::filesystem::path folder = [] {
    const std::filesystem::path path =
        std::filesystem::temp_directory_path() / ("syn-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(path);
    return path;
  }();
  const std::string path = (folder / file_name).string();
  FILE* file = std::fopen(path.c_str(), "wb");
  if (file == nullptr) std::abort();  // the fuzzer's own setup, not the code under test
  if (size > 0 && data != nullptr && std::fwrite(data, 1, size, file) != size) std::abort();
  std::fclose(file);
  return path;
}

}  // namespace syn::fuzzing
