// Scratch files and folders in the temporary folder that tests leave nothing behind in, however they end: a
// file removed when it goes out of scope (a URDF written for a moment), and a per-process folder removed
// when the test program ends.
#pragma once

#include <unistd.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

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

// The folder <tmp>/<prefix><pid>, created; it and everything in it are removed when the test program ends.
inline std::filesystem::path ProcessScratchDir(const std::string& prefix) {
  struct RemovedAtExit {
    std::vector<std::filesystem::path> paths;
    ~RemovedAtExit() {
      std::error_code ignored;
      for (const std::filesystem::path& path : paths) std::filesystem::remove_all(path, ignored);
    }
  };
  static RemovedAtExit folders;
  const std::filesystem::path path = std::filesystem::temp_directory_path() / (prefix + std::to_string(::getpid()));
  if (std::find(folders.paths.begin(), folders.paths.end(), path) == folders.paths.end()) folders.paths.push_back(path);
  std::filesystem::create_directories(path);
  return path;
}

}  // namespace syn::testing
