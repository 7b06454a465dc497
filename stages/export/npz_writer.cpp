#include "stages/export/npz_writer.h"

#include <array>
#include <cstring>
#include <stdexcept>

namespace syn {
namespace {

void PutLittle(std::string& out, uint64_t value, int bytes) {
  for (int i = 0; i < bytes; ++i) out += static_cast<char>((value >> (8 * i)) & 0xFF);
}

// UTF-8 -> code points (the text is valid UTF-8: motion and model names come from our own files).
std::vector<uint32_t> CodePoints(const std::string& text) {
  std::vector<uint32_t> points;
  for (size_t i = 0; i < text.size();) {
    const auto lead = static_cast<uint8_t>(text[i]);
    const size_t length = lead < 0x80 ? 1 : (lead & 0xE0) == 0xC0 ? 2 : (lead & 0xF0) == 0xE0 ? 3 : 4;
    uint32_t code = length == 1 ? lead : length == 2 ? (lead & 0x1F) : length == 3 ? (lead & 0x0F) : (lead & 0x07);
    for (size_t k = 1; k < length && i + k < text.size(); ++k) code = (code << 6) | (static_cast<uint8_t>(text[i + k]) & 0x3F);
    points.push_back(code);
    i += length;
  }
  return points;
}

std::string ShapeText(const std::vector<int64_t>& shape) {
  std::string text = "(";
  for (size_t i = 0; i < shape.size(); ++i) text += (i ? ", " : "") + std::to_string(shape[i]);
  if (shape.size() == 1) text += ",";
  return text + ")";
}

}  // namespace

uint32_t Crc32(const std::string& bytes) {
  static const std::array<uint32_t, 256> table = [] {
    std::array<uint32_t, 256> entries{};
    for (uint32_t n = 0; n < 256; ++n) {
      uint32_t c = n;
      for (int k = 0; k < 8; ++k) c = (c & 1) ? 0xEDB88320u ^ (c >> 1) : c >> 1;
      entries[n] = c;
    }
    return entries;
  }();
  uint32_t crc = 0xFFFFFFFFu;
  for (char byte : bytes) crc = table[(crc ^ static_cast<uint8_t>(byte)) & 0xFF] ^ (crc >> 8);
  return crc ^ 0xFFFFFFFFu;
}

std::string NpyBytes(const NpyArray& array) {
  std::string descr, data;
  std::vector<int64_t> shape = array.shape;
  if (array.text) {
    std::vector<std::vector<uint32_t>> texts;
    size_t width = 1;
    for (const std::string& text : array.strings) {
      texts.push_back(CodePoints(text));
      width = std::max(width, texts.back().size());
    }
    descr = "<U" + std::to_string(width);
    shape = {static_cast<int64_t>(texts.size())};
    for (const auto& text : texts) {
      for (size_t k = 0; k < width; ++k) PutLittle(data, k < text.size() ? text[k] : 0, 4);
    }
  } else {
    int64_t count = 1;
    for (int64_t dimension : shape) count *= dimension;
    if (count != static_cast<int64_t>(array.values.size())) {
      throw std::invalid_argument("NPY array '" + array.name + "': " + std::to_string(array.values.size()) +
                                  " values for shape " + ShapeText(shape));
    }
    descr = "<f8";
    data.resize(array.values.size() * 8);
    for (size_t i = 0; i < array.values.size(); ++i) {
      uint64_t bits;
      std::memcpy(&bits, &array.values[i], 8);
      for (int b = 0; b < 8; ++b) data[i * 8 + static_cast<size_t>(b)] = static_cast<char>((bits >> (8 * b)) & 0xFF);
    }
  }
  std::string header = "{'descr': '" + descr + "', 'fortran_order': False, 'shape': " + ShapeText(shape) + ", }";
  const size_t preamble = 10;  // magic (6), version (2), header length (2)
  const size_t padded = ((preamble + header.size() + 1 + 63) / 64) * 64;
  header.append(padded - preamble - header.size() - 1, ' ');
  header += '\n';
  std::string out = "\x93NUMPY";
  out += '\x01';
  out += '\x00';
  PutLittle(out, header.size(), 2);
  return out + header + data;
}

std::string NpzBytes(const std::vector<NpyArray>& arrays) {
  constexpr uint16_t kDosTime = 0, kDosDate = (0 << 9) | (1 << 5) | 1;  // 1980-01-01 00:00:00
  std::string archive, directory;
  for (const NpyArray& array : arrays) {
    const std::string name = array.name + ".npy";
    const std::string member = NpyBytes(array);
    const uint32_t crc = Crc32(member);
    const size_t offset = archive.size();
    // Local file header.
    PutLittle(archive, 0x04034b50, 4);
    PutLittle(archive, 20, 2);  // version needed: 2.0
    PutLittle(archive, 0, 2);   // flags
    PutLittle(archive, 0, 2);   // method: STORE
    PutLittle(archive, kDosTime, 2);
    PutLittle(archive, kDosDate, 2);
    PutLittle(archive, crc, 4);
    PutLittle(archive, member.size(), 4);
    PutLittle(archive, member.size(), 4);
    PutLittle(archive, name.size(), 2);
    PutLittle(archive, 0, 2);  // extra length
    archive += name;
    archive += member;
    // Central directory entry.
    PutLittle(directory, 0x02014b50, 4);
    PutLittle(directory, 20, 2);  // version made by
    PutLittle(directory, 20, 2);  // version needed
    PutLittle(directory, 0, 2);
    PutLittle(directory, 0, 2);
    PutLittle(directory, kDosTime, 2);
    PutLittle(directory, kDosDate, 2);
    PutLittle(directory, crc, 4);
    PutLittle(directory, member.size(), 4);
    PutLittle(directory, member.size(), 4);
    PutLittle(directory, name.size(), 2);
    PutLittle(directory, 0, 2);  // extra
    PutLittle(directory, 0, 2);  // comment
    PutLittle(directory, 0, 2);  // disk
    PutLittle(directory, 0, 2);  // internal attributes
    PutLittle(directory, 0, 4);  // external attributes
    PutLittle(directory, offset, 4);
    directory += name;
  }
  if (archive.size() + directory.size() >= 0xFFFFFFFFu) {
    throw std::invalid_argument("NPZ archive over 4 GiB: zip64 is not written");
  }
  const size_t directory_offset = archive.size();
  archive += directory;
  PutLittle(archive, 0x06054b50, 4);
  PutLittle(archive, 0, 2);
  PutLittle(archive, 0, 2);
  PutLittle(archive, arrays.size(), 2);
  PutLittle(archive, arrays.size(), 2);
  PutLittle(archive, directory.size(), 4);
  PutLittle(archive, directory_offset, 4);
  PutLittle(archive, 0, 2);  // comment length
  return archive;
}

}  // namespace syn
