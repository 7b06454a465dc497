// A deterministic POSIX ustar writer and a small ustar/GNU/pax reader, for syn-release. No libarchive:
// the release needs only regular files and folders, and a fixed header (mtime 0, uid/gid 0, no user
// names, mode 0644 / 0755) is what makes two builds of the same files byte-identical.
#pragma once

#include <cstdint>
#include <fstream>
#include <string>
#include <vector>

namespace syn {

struct TarMember {
  std::string name;  // as stored, without a trailing '/'
  bool directory = false;
  uint64_t size = 0;
  uint64_t header_offset = 0;  // byte offset of the member's (first) header block in the tar
};

// Writes NAME.tmp-<pid>; commit() renames it onto NAME, the destructor removes an uncommitted one.
// Members are written in the order they are added: the caller sorts them.
class TarWriter {
 public:
  explicit TarWriter(std::string path);
  ~TarWriter();
  TarWriter(const TarWriter&) = delete;
  TarWriter& operator=(const TarWriter&) = delete;

  void addDirectory(const std::string& name);
  void addBytes(const std::string& name, const std::string& bytes);
  // Streams `disk_path` into the archive. Throws DataError if it cannot be read.
  void addFile(const std::string& name, const std::string& disk_path);
  // Two zero blocks, padding to a whole 10240-byte record (as tar(1) writes), then the rename.
  void commit();
  uint64_t size() const { return written_; }

 private:
  void writeHeader(const std::string& name, char type, uint64_t size, uint32_t mode);
  void write(const char* data, size_t size);
  void pad();

  std::string path_;
  std::string temporary_path_;
  std::ofstream out_;
  uint64_t written_ = 0;
  bool committed_ = false;
};

// Extracts every member of `tar_path` under `into` (which must exist), refusing absolute names, '..'
// components, links and devices. A bad header checksum, a truncated member or an unsupported member type
// is a DataError at the tar's byte offset. Returns the members in archive order.
std::vector<TarMember> ExtractTar(const std::string& tar_path, const std::string& into);

}  // namespace syn
