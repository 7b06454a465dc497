#include "tools/release/tar_archive.h"

#include <unistd.h>

#include <algorithm>
#include <array>
#include <cstring>
#include <filesystem>
#include <utility>

#include "common/error.h"

namespace syn {
namespace {

constexpr size_t kBlock = 512;
constexpr size_t kRecord = 10240;  // tar(1)'s default blocking factor 20

// Field offsets and widths of a ustar header (POSIX.1-1988).
struct Field {
  size_t offset, width;
};
constexpr Field kName{0, 100}, kMode{100, 8}, kUid{108, 8}, kGid{116, 8}, kSize{124, 12}, kMtime{136, 12},
    kChecksum{148, 8}, kType{156, 1}, kMagic{257, 6}, kVersion{263, 2}, kPrefix{345, 155};

void PutOctal(std::array<char, kBlock>& header, Field field, uint64_t value) {
  // width-1 octal digits, zero-padded, then NUL (the header starts zeroed). Callers keep values in range.
  for (size_t i = field.width - 1; i-- > 0; value >>= 3) header[field.offset + i] = static_cast<char>('0' + (value & 7));
}

void PutText(std::array<char, kBlock>& header, Field field, const std::string& text) {
  std::memcpy(&header[field.offset], text.data(), std::min(text.size(), field.width));
}

unsigned HeaderChecksum(const std::array<char, kBlock>& header) {
  unsigned sum = 0;
  for (size_t i = 0; i < kBlock; ++i) {
    const bool in_field = i >= kChecksum.offset && i < kChecksum.offset + kChecksum.width;
    sum += in_field ? ' ' : static_cast<unsigned char>(header[i]);
  }
  return sum;
}

}  // namespace

TarWriter::TarWriter(std::string path) : path_(std::move(path)) {
  temporary_path_ = path_ + ".tmp-" + std::to_string(::getpid());
  out_.open(temporary_path_, std::ios::binary | std::ios::trunc);
  if (!out_) throw DataError(Location::InFile(temporary_path_), "cannot create it");
}

TarWriter::~TarWriter() {
  if (committed_) return;
  out_.close();
  std::error_code ignored;
  std::filesystem::remove(temporary_path_, ignored);
}

void TarWriter::write(const char* data, size_t size) {
  out_.write(data, static_cast<std::streamsize>(size));
  if (!out_) throw DataError(Location::InFile(temporary_path_), "write failed (disk full?)");
  written_ += size;
}

void TarWriter::pad() {
  static const std::array<char, kBlock> zeros{};
  if (written_ % kBlock != 0) write(zeros.data(), kBlock - written_ % kBlock);
}

void TarWriter::writeHeader(const std::string& name, char type, uint64_t size, uint32_t mode) {
  std::array<char, kBlock> header{};
  // A long name goes into prefix + '/' + name, split at a '/'.
  std::string prefix, base = name;
  if (name.size() > kName.width) {
    size_t split = name.rfind('/', kPrefix.width);
    while (split != std::string::npos && split > 0 && name.size() - split - 1 > kName.width) split = std::string::npos;
    if (split == std::string::npos || split == 0) {
      throw DataError(Location::InFile(path_), "member name too long for a ustar header (" +
                                                   std::to_string(name.size()) + " characters): " + name);
    }
    prefix = name.substr(0, split);
    base = name.substr(split + 1);
  }
  if (size >= (uint64_t{1} << 33)) throw DataError(Location::InFile(path_), "member larger than 8 GiB: " + name);
  PutText(header, kName, base);
  PutOctal(header, kMode, mode);
  PutOctal(header, kUid, 0);
  PutOctal(header, kGid, 0);
  PutOctal(header, kSize, size);
  PutOctal(header, kMtime, 0);
  header[kType.offset] = type;
  PutText(header, kMagic, std::string("ustar\0", 6));
  PutText(header, kVersion, "00");
  PutText(header, kPrefix, prefix);
  // Six octal digits, NUL, space: the checksum field as tar(1) writes it.
  unsigned checksum = HeaderChecksum(header);
  for (size_t i = 6; i-- > 0; checksum >>= 3) header[kChecksum.offset + i] = static_cast<char>('0' + (checksum & 7));
  header[kChecksum.offset + 6] = '\0';
  header[kChecksum.offset + 7] = ' ';
  write(header.data(), kBlock);
}

void TarWriter::addDirectory(const std::string& name) { writeHeader(name + "/", '5', 0, 0755); }

void TarWriter::addBytes(const std::string& name, const std::string& bytes) {
  writeHeader(name, '0', bytes.size(), 0644);
  write(bytes.data(), bytes.size());
  pad();
}

void TarWriter::addFile(const std::string& name, const std::string& disk_path) {
  std::ifstream in(disk_path, std::ios::binary);
  if (!in) throw DataError(Location::InFile(disk_path), "cannot open it");
  std::error_code error;
  const uint64_t size = std::filesystem::file_size(disk_path, error);
  if (error) throw DataError(Location::InFile(disk_path), "cannot read its size: " + error.message());
  writeHeader(name, '0', size, 0644);
  std::vector<char> buffer(1 << 20);
  uint64_t copied = 0;
  while (copied < size) {
    in.read(buffer.data(), static_cast<std::streamsize>(std::min<uint64_t>(buffer.size(), size - copied)));
    const auto got = static_cast<size_t>(in.gcount());
    if (got == 0) throw DataError(Location::AtByte(disk_path, static_cast<int64_t>(copied)), "file shrank while being archived");
    write(buffer.data(), got);
    copied += got;
  }
  pad();
}

void TarWriter::commit() {
  static const std::array<char, kBlock> zeros{};
  write(zeros.data(), kBlock);
  write(zeros.data(), kBlock);
  while (written_ % kRecord != 0) write(zeros.data(), kBlock);
  out_.close();
  if (!out_) throw DataError(Location::InFile(temporary_path_), "close failed");
  std::error_code error;
  std::filesystem::rename(temporary_path_, path_, error);
  if (error) throw DataError(Location::InFile(path_), "cannot rename " + temporary_path_ + " onto it: " + error.message());
  committed_ = true;
}

namespace {

// An octal field (NUL/space terminated), or GNU's base-256 form (high bit of the first byte set).
bool ParseNumber(const char* field, size_t width, uint64_t& value) {
  value = 0;
  if (static_cast<unsigned char>(field[0]) & 0x80) {
    for (size_t i = 1; i < width; ++i) value = (value << 8) | static_cast<unsigned char>(field[i]);
    return true;
  }
  size_t i = 0;
  while (i < width && field[i] == ' ') ++i;
  bool digits = false;
  for (; i < width && field[i] >= '0' && field[i] <= '7'; ++i, digits = true) value = value * 8 + static_cast<uint64_t>(field[i] - '0');
  return digits && (i == width || field[i] == '\0' || field[i] == ' ');
}

std::string FieldText(const char* field, size_t width) { return std::string(field, strnlen(field, width)); }

// A member name that cannot escape the extraction folder.
bool SafeName(const std::string& name) {
  if (name.empty() || name.front() == '/') return false;
  for (const auto& part : std::filesystem::path(name)) {
    if (part == "..") return false;
  }
  return true;
}

// The "path" record of a pax extended header ("LEN path=VALUE\n" records), or "".
std::string PaxPath(const std::string& records) {
  size_t at = 0;
  while (at < records.size()) {
    const size_t space = records.find(' ', at);
    if (space == std::string::npos) break;
    const size_t length = std::strtoull(records.c_str() + at, nullptr, 10);
    if (length == 0 || at + length > records.size()) break;
    const std::string record = records.substr(space + 1, at + length - space - 2);  // without the '\n'
    if (record.rfind("path=", 0) == 0) return record.substr(5);
    at += length;
  }
  return "";
}

}  // namespace

std::vector<TarMember> ExtractTar(const std::string& tar_path, const std::string& into) {
  std::ifstream in(tar_path, std::ios::binary);
  if (!in) throw DataError(Location::InFile(tar_path), "cannot open it");
  std::vector<TarMember> members;
  std::array<char, kBlock> header{};
  std::vector<char> buffer(1 << 20);
  uint64_t offset = 0;
  std::string long_name;  // from a GNU 'L' or pax 'x' header, for the next member
  const auto fail = [&](uint64_t at, const std::string& message) -> DataError {
    return DataError(Location::AtByte(tar_path, static_cast<int64_t>(at)), message);
  };
  // Reads `size` bytes of member data (padded to a block): into `sink` when given, else into `text`.
  const auto read_data = [&](uint64_t size, std::ofstream* sink, std::string* text, const std::string& name) {
    uint64_t left = size;
    while (left > 0) {
      in.read(buffer.data(), static_cast<std::streamsize>(std::min<uint64_t>(buffer.size(), left)));
      const auto got = static_cast<size_t>(in.gcount());
      if (got == 0) throw fail(offset + (size - left), "member '" + name + "' is truncated (" + std::to_string(left) + " of its " + std::to_string(size) + " bytes missing)");
      if (sink) sink->write(buffer.data(), static_cast<std::streamsize>(got));
      if (text) text->append(buffer.data(), got);
      left -= got;
    }
    const uint64_t padded = (size + kBlock - 1) / kBlock * kBlock;
    in.ignore(static_cast<std::streamsize>(padded - size));
    offset += padded;
  };
  while (true) {
    in.read(header.data(), kBlock);
    if (in.gcount() == 0) break;  // end of file without the end-of-archive blocks: tolerated
    if (static_cast<size_t>(in.gcount()) != kBlock) throw fail(offset, "truncated header block");
    const uint64_t header_offset = offset;
    offset += kBlock;
    if (std::all_of(header.begin(), header.end(), [](char c) { return c == 0; })) break;  // end of archive
    uint64_t stored_checksum = 0, size = 0;
    if (!ParseNumber(&header[kChecksum.offset], kChecksum.width, stored_checksum) || stored_checksum != HeaderChecksum(header)) {
      throw fail(header_offset, "tar header checksum mismatch (not a tar file, or a damaged header)");
    }
    if (!ParseNumber(&header[kSize.offset], kSize.width, size)) throw fail(header_offset + kSize.offset, "bad size field");
    const char type = header[kType.offset];
    std::string name = FieldText(&header[kName.offset], kName.width);
    if (FieldText(&header[kMagic.offset], 5) == "ustar") {
      const std::string prefix = FieldText(&header[kPrefix.offset], kPrefix.width);
      if (!prefix.empty()) name = prefix + "/" + name;
    }
    if (!long_name.empty()) name = std::exchange(long_name, std::string());
    if (type == 'L' || type == 'x' || type == 'g') {  // GNU long name; pax extended / global header
      std::string data;
      read_data(size, nullptr, &data, name);
      if (type == 'L') long_name = FieldText(data.data(), data.size());
      if (type == 'x') long_name = PaxPath(data);
      continue;
    }
    while (!name.empty() && name.back() == '/') name.pop_back();
    if (name == "." || name.empty()) {
      if (type != '5') throw fail(header_offset, "member with an empty name");
      continue;
    }
    if (name.rfind("./", 0) == 0) name = name.substr(2);
    if (!SafeName(name)) throw fail(header_offset, "unsafe member name '" + name + "' (absolute or with '..')");
    TarMember member{name, type == '5', size, header_offset};
    const std::filesystem::path target = std::filesystem::path(into) / name;
    std::error_code error;
    if (type == '5') {
      std::filesystem::create_directories(target, error);
      if (error) throw DataError(Location::InFile(target.string()), "cannot create folder: " + error.message());
    } else if (type == '0' || type == '\0' || type == '7') {
      std::filesystem::create_directories(target.parent_path(), error);
      if (error) throw DataError(Location::InFile(target.parent_path().string()), "cannot create folder: " + error.message());
      std::ofstream out(target, std::ios::binary | std::ios::trunc);
      if (!out) throw DataError(Location::InFile(target.string()), "cannot create it");
      read_data(size, &out, nullptr, name);
      if (!out) throw DataError(Location::InFile(target.string()), "write failed (disk full?)");
    } else {
      throw fail(header_offset, "member '" + name + "' has type '" + std::string(1, type) +
                                    "' (a release holds only files and folders)");
    }
    members.push_back(member);
  }
  return members;
}

}  // namespace syn
