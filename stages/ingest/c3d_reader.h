// C3D motion-capture files (c3d.org): a 512-byte header, a parameter section
// of groups and parameters, and a data section of 3D points and analog
// samples, written by Intel (little-endian), DEC (VAX floats) or MIPS
// (big-endian) processors, as scaled int16 or as floats.
//
// The reader follows the header's block pointers (not assumed positions),
// falls back to the header where parameters are missing or wrong, and reads
// the frames a truncated file holds (with a warning). Invalid samples become
// NaN: a negative residual word (the C3D rule), or a sample written as exactly
// (0, 0, 0) — the gap convention of Vicon, OptiTrack and Qualisys QTM, whose
// gaps carry a positive residual 65535. Labels are kept as written
// (duplicates and subject prefixes included); lengths stay in POINT:UNITS.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "common/marker_data.h"

namespace syn {

// Throws DataError at a byte offset for what cannot be read at all.
[[nodiscard]] MarkerData ParseC3d(const uint8_t* bytes, size_t size, const std::string& source_name);
[[nodiscard]] MarkerData ReadC3d(const std::string& path);

// One record of the parameter section, decoded in the file's processor format: a group (key "GROUP:",
// type 0) or a parameter (key "GROUP:NAME"). For inspection and for checking that Intel, DEC and MIPS
// copies of one trial agree field by field.
struct C3dParameter {
  std::string key;
  int type = 0;                      // -1 char, 1 byte, 2 int16, 4 float; 0 for a group
  std::vector<int> dimensions;
  std::vector<double> numbers;       // types 1, 2, 4 (bytes unsigned, int16 signed)
  std::vector<std::string> strings;  // type -1: first dimension = string length, trailing blanks removed
  bool locked = false;               // a negative name length
  std::string description;
};
// Sorted by key. Empty when the file has no readable parameter section.
[[nodiscard]] std::vector<C3dParameter> ParseC3dParameters(const uint8_t* bytes, size_t size,
                                                           const std::string& source_name);

}  // namespace syn
