// NumPy .npy arrays and .npz archives (a zip of .npy members), written byte for byte without numpy:
// what `np.load(path)` reads with allow_pickle=False.
//
// NPY format 1.0: magic "\x93NUMPY", version 1.0, a little-endian uint16 header length, then a Python
// dict literal {'descr': ..., 'fortran_order': False, 'shape': (...), } padded with spaces and ended by
// "\n" so the data starts at a multiple of 64 bytes, then the values in C order.
// NPZ: a zip archive, members "<name>.npy" stored uncompressed (method 0, STORE), CRC-32 checked, with
// a fixed timestamp (1980-01-01 00:00) so the same arrays give the same bytes.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace syn {

struct NpyArray {
  std::string name;              // member name without ".npy"
  std::vector<int64_t> shape;    // empty = a 0-d scalar
  std::vector<double> values;    // float64 ('<f8'), C order (numbers)
  bool text = false;             // true: `strings` instead of `values`
  std::vector<std::string> strings;  // UTF-8 text -> fixed-width unicode ('<U<n>', UTF-32LE); shape [count]

  static NpyArray Numbers(std::string name, std::vector<int64_t> shape, std::vector<double> values = {}) {
    return {std::move(name), std::move(shape), std::move(values), false, {}};
  }
  static NpyArray Text(std::string name, std::vector<std::string> strings) {
    return {std::move(name), {}, {}, true, std::move(strings)};
  }
};

// One .npy file's bytes. Throws std::invalid_argument if values.size() does not match the shape.
[[nodiscard]] std::string NpyBytes(const NpyArray& array);
// The .npz archive's bytes (members in the given order).
[[nodiscard]] std::string NpzBytes(const std::vector<NpyArray>& arrays);

// CRC-32 (IEEE 802.3, as zip uses) of `bytes`.
[[nodiscard]] uint32_t Crc32(const std::string& bytes);

}  // namespace syn
