// A file in the temporary folder that is removed when it goes out of scope, so that a test that writes a URDF
// (or any input) for a moment leaves nothing behind, however it ends.
#pragma once

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <string>

namespace syn::testing {

class ScratchFile {
 public:
  // The file <tmp>/<stem>_<pid><extension>, holding `text`.
  ScratchFile(const std::string& stem, const std::string& extension, const std::string& text)
      : path_(std::filesystem::temp_directory_path() / (stem + "_" + std::to_string(::getpid()) + extension)) {
    std::ofstream(path_) << text;
  }
  ~ScratchFile() {
    std::error_code ignored;
    std::filesystem::remove(path_, ignored);
  }
  ScratchFile(const ScratchFile&) = delete;
  ScratchFile& operator=(const ScratchFile&) = delete;

  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

}  // namespace syn::testing
