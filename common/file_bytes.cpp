#include "common/file_bytes.h"

#include <cerrno>
#include <cstdlib>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <memory>

#include <unistd.h>

#include "common/error.h"

namespace syn {
namespace {

template <typename Buffer>
Buffer ReadAll(const std::string& path) {
  std::unique_ptr<FILE, int (*)(FILE*)> file(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!file) throw DataError(Location::InFile(path), std::string("cannot open: ") + std::strerror(errno));
  if (std::fseek(file.get(), 0, SEEK_END) != 0) {
    throw DataError(Location::InFile(path), "cannot seek (not a regular file?)");
  }
  const long size = std::ftell(file.get());
  if (size < 0) throw DataError(Location::InFile(path), "cannot tell file size");
  std::rewind(file.get());
  Buffer bytes(static_cast<size_t>(size), 0);
  if (size > 0 && std::fread(bytes.data(), 1, bytes.size(), file.get()) != bytes.size()) {
    throw DataError(Location::InFile(path), std::string("read failed: ") + std::strerror(errno));
  }
  return bytes;
}

}  // namespace

std::vector<uint8_t> ReadFileBytes(const std::string& path) { return ReadAll<std::vector<uint8_t>>(path); }
std::string ReadFileText(const std::string& path) { return ReadAll<std::string>(path); }

void PauseBeforeRenameIfRequested(const std::string& path, const std::string& temporary) {
  const char* suffix = std::getenv("SYN_TEST_PAUSE_BEFORE_RENAME");
  if (suffix == nullptr || *suffix == '\0') return;
  const std::string wanted(suffix);
  if (path.size() < wanted.size() || path.compare(path.size() - wanted.size(), wanted.size(), wanted) != 0) return;
  std::fprintf(stderr, "syn: test hook: paused before renaming %s\n", temporary.c_str());
  std::fflush(stderr);
  for (int second = 0; second < 120; ++second) ::sleep(1);
}

void WriteFileAtomically(const std::string& path, const std::string& text) {
  const std::string temporary = path + ".tmp-" + std::to_string(::getpid());
  {
    std::ofstream out(temporary, std::ios::binary);
    out << text;
    out.flush();
    if (!out) {
      std::remove(temporary.c_str());
      throw DataError(Location::InFile(path), "cannot write " + temporary);
    }
  }
  PauseBeforeRenameIfRequested(path, temporary);
  std::error_code error;
  std::filesystem::rename(temporary, path, error);
  if (error) {
    std::remove(temporary.c_str());
    throw DataError(Location::InFile(path), "cannot rename " + temporary + ": " + error.message());
  }
}

}  // namespace syn
