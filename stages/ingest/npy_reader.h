// NumPy .npy arrays (format versions 1–3), and HumanML3D joint files made of
// them: [T, 22, 3] joint positions, metres, Y up, 20 frames per second.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "common/marker_data.h"

namespace syn {

struct NpyArray {
  std::string dtype;             // as in the header, e.g. "<f4"
  std::vector<int64_t> shape;
  bool fortran_order = false;
  std::vector<double> values;    // C order, converted to double
};

// Reads numeric arrays (little- or big-endian floats and integers of 1–8
// bytes, bool). Refuses object arrays ("|O", e.g. an MDM results.npy holding a
// pickled dict) with a message naming the plain files to use instead. Errors
// are DataErrors at byte offsets.
[[nodiscard]] NpyArray ParseNpy(const uint8_t* bytes, size_t size, const std::string& source_name);

// SMPL joint order of HumanML3D's 22 joints, and each joint's parent ("" for the pelvis).
extern const char* const kHumanMl3dJointNames[22];
extern const int kHumanMl3dJointParents[22];

// [T, 22, 3] -> 22 bodies with positions (orientation NaN: joints have none).
// A [T, 263] feature-vector file is refused with a message that says so.
[[nodiscard]] MarkerData HumanMl3dJointsToMarkerData(const NpyArray& array, const std::string& source_name);
[[nodiscard]] MarkerData ReadHumanMl3dJoints(const std::string& path);

}  // namespace syn
