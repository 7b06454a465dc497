#include "stages/ingest/npy_reader.h"

#include <charconv>
#include <cmath>
#include <cstring>
#include <limits>

#include "common/error.h"
#include "common/file_bytes.h"

namespace syn {

const char* const kHumanMl3dJointNames[22] = {
    "pelvis",     "left_hip",     "right_hip",    "spine1",         "left_knee",       "right_knee",
    "spine2",     "left_ankle",   "right_ankle",  "spine3",         "left_foot",       "right_foot",
    "neck",       "left_collar",  "right_collar", "head",           "left_shoulder",   "right_shoulder",
    "left_elbow", "right_elbow",  "left_wrist",   "right_wrist"};
const int kHumanMl3dJointParents[22] = {-1, 0, 0, 0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 9, 9, 12, 13, 14, 16, 17, 18, 19};

namespace {

// Value of `key` in the header dict, e.g. 'descr': '<f4' -> "<f4" (quotes kept off), or the raw text.
std::string DictValue(const std::string& header, const std::string& key, const std::string& source, size_t offset) {
  const size_t at = header.find("'" + key + "'");
  if (at == std::string::npos) throw DataError(Location::AtByte(source, static_cast<int64_t>(offset)), "NPY header has no '" + key + "'");
  size_t start = header.find(':', at);
  if (start == std::string::npos) throw DataError(Location::AtByte(source, static_cast<int64_t>(offset)), "malformed NPY header");
  ++start;
  while (start < header.size() && header[start] == ' ') ++start;
  if (start < header.size() && header[start] == '\'') {
    const size_t end = header.find('\'', start + 1);
    if (end == std::string::npos) throw DataError(Location::AtByte(source, static_cast<int64_t>(offset)), "malformed NPY header");
    return header.substr(start + 1, end - start - 1);
  }
  if (start < header.size() && header[start] == '(') {
    const size_t end = header.find(')', start);
    if (end == std::string::npos) throw DataError(Location::AtByte(source, static_cast<int64_t>(offset)), "malformed NPY shape");
    return header.substr(start + 1, end - start - 1);
  }
  size_t end = start;
  while (end < header.size() && header[end] != ',' && header[end] != '}') ++end;
  return header.substr(start, end - start);
}

template <typename T>
T Load(const uint8_t* p, bool swap) {
  uint8_t buffer[sizeof(T)];
  std::memcpy(buffer, p, sizeof(T));
  if (swap) {
    for (size_t i = 0; i < sizeof(T) / 2; ++i) std::swap(buffer[i], buffer[sizeof(T) - 1 - i]);
  }
  T value;
  std::memcpy(&value, buffer, sizeof(T));
  return value;
}

}  // namespace

NpyArray ParseNpy(const uint8_t* bytes, size_t size, const std::string& source_name) {
  const auto fail = [&](size_t offset, const std::string& message) {
    return DataError(Location::AtByte(source_name, static_cast<int64_t>(offset)), message);
  };
  if (size < 10 || std::memcmp(bytes, "\x93NUMPY", 6) != 0) throw fail(0, "not an NPY file (expected the magic \\x93NUMPY)");
  const int major = bytes[6];
  size_t header_length = 0, header_start = 0;
  if (major == 1) {
    header_length = bytes[8] | (static_cast<size_t>(bytes[9]) << 8);
    header_start = 10;
  } else if (major == 2 || major == 3) {
    if (size < 12) throw fail(8, "truncated NPY header");
    header_length = bytes[8] | (static_cast<size_t>(bytes[9]) << 8) | (static_cast<size_t>(bytes[10]) << 16) |
                    (static_cast<size_t>(bytes[11]) << 24);
    header_start = 12;
  } else {
    throw fail(6, "unsupported NPY format version " + std::to_string(major));
  }
  if (header_length > size - header_start) throw fail(8, "the NPY header runs past the end of the file");
  const std::string header(reinterpret_cast<const char*>(bytes + header_start), header_length);
  NpyArray array;
  array.dtype = DictValue(header, "descr", source_name, header_start);
  array.fortran_order = DictValue(header, "fortran_order", source_name, header_start).find("True") != std::string::npos;
  const std::string shape = DictValue(header, "shape", source_name, header_start);
  size_t position = 0;
  while (position < shape.size()) {
    while (position < shape.size() && (shape[position] == ' ' || shape[position] == ',')) ++position;
    if (position >= shape.size()) break;
    size_t end = position;
    while (end < shape.size() && std::isdigit(static_cast<unsigned char>(shape[end]))) ++end;
    if (end == position) throw fail(header_start, "malformed NPY shape (" + shape + ")");
    int64_t dimension = 0;
    const auto [parsed, error] = std::from_chars(shape.data() + position, shape.data() + end, dimension);
    if (error != std::errc() || parsed != shape.data() + end) {
      throw fail(header_start, "NPY shape dimension out of range (" + shape + ")");
    }
    array.shape.push_back(dimension);
    position = end;
  }
  if (array.dtype.find('O') != std::string::npos) {
    throw fail(header_start, "an object array ('" + array.dtype +
                                 "', e.g. an MDM results.npy holding a pickled dict) cannot be read; export the motions "
                                 "as plain [T, 22, 3] float arrays (see humanml3d/derived/ in the shared datasets)");
  }
  if (array.dtype.size() < 3) throw fail(header_start, "unsupported NPY dtype '" + array.dtype + "'");
  const char order = array.dtype[0];
  const char kind = array.dtype[1];
  const int width = std::atoi(array.dtype.c_str() + 2);
  const bool swap = order == '>';  // this machine is little-endian
  if (order != '<' && order != '>' && order != '|' && order != '=') throw fail(header_start, "unsupported byte order in '" + array.dtype + "'");
  const bool known = (kind == 'f' && (width == 4 || width == 8)) || ((kind == 'i' || kind == 'u') && (width == 1 || width == 2 || width == 4 || width == 8)) ||
                     (kind == 'b' && width == 1);
  if (!known) throw fail(header_start, "unsupported NPY dtype '" + array.dtype + "' (expected floats, integers or bool)");
  uint64_t count = 1;
  for (int64_t dimension : array.shape) {
    if (dimension < 0 || (dimension > 0 && count > std::numeric_limits<uint64_t>::max() / static_cast<uint64_t>(dimension))) {
      throw fail(header_start, "NPY shape too large");
    }
    count *= static_cast<uint64_t>(dimension);
  }
  const size_t data_start = header_start + header_length;
  if (count > (size - data_start) / static_cast<size_t>(width)) {
    throw fail(data_start, "the file holds " + std::to_string(size - data_start) + " data bytes; shape and dtype need " +
                               std::to_string(count * static_cast<uint64_t>(width)));
  }
  array.values.resize(count);
  const uint8_t* data = bytes + data_start;
  for (uint64_t i = 0; i < count; ++i) {
    const uint8_t* p = data + i * static_cast<uint64_t>(width);
    double value = 0;
    if (kind == 'f') value = width == 4 ? Load<float>(p, swap) : Load<double>(p, swap);
    else if (kind == 'b') value = *p != 0;
    else if (kind == 'i') value = width == 1 ? static_cast<int8_t>(*p) : width == 2 ? Load<int16_t>(p, swap) : width == 4 ? Load<int32_t>(p, swap) : static_cast<double>(Load<int64_t>(p, swap));
    else value = width == 1 ? *p : width == 2 ? Load<uint16_t>(p, swap) : width == 4 ? Load<uint32_t>(p, swap) : static_cast<double>(Load<uint64_t>(p, swap));
    array.values[i] = value;
  }
  if (array.fortran_order && array.shape.size() > 1) {
    // Reorder to C order: element (i0, i1, ...) sits at Σ i_k · stride_k with the first index fastest.
    std::vector<double> c_order(array.values.size());
    std::vector<int64_t> index(array.shape.size(), 0);
    for (size_t linear = 0; linear < c_order.size(); ++linear) {
      size_t fortran = 0, stride = 1;
      for (size_t k = 0; k < array.shape.size(); ++k) fortran += static_cast<size_t>(index[k]) * stride, stride *= static_cast<size_t>(array.shape[k]);
      c_order[linear] = array.values[fortran];
      for (size_t k = array.shape.size(); k-- > 0;) {
        if (++index[k] < array.shape[k]) break;
        index[k] = 0;
      }
    }
    array.values.swap(c_order);
    array.fortran_order = false;
  }
  return array;
}

MarkerData HumanMl3dJointsToMarkerData(const NpyArray& array, const std::string& source_name) {
  if (array.shape.size() == 2 && array.shape[1] == 263) {
    throw DataError(Location::InFile(source_name), "this is a [T, 263] HumanML3D feature-vector file, not joint positions; "
                                                   "use the matching new_joints [T, 22, 3] file");
  }
  if (array.shape.size() != 3 || array.shape[1] != 22 || array.shape[2] != 3) {
    std::string shape;
    for (int64_t d : array.shape) shape += (shape.empty() ? "" : ", ") + std::to_string(d);
    throw DataError(Location::InFile(source_name), "expected HumanML3D joints of shape [T, 22, 3], found [" + shape + "]");
  }
  MarkerData data;
  data.rate_hz = 20.0;  // HumanML3D's frame rate
  data.up_axis = 'y';
  data.length_unit_to_m = 1.0;
  for (int j = 0; j < 22; ++j) {
    data.bodies.emplace_back(kHumanMl3dJointNames[j]);
    data.body_parents.emplace_back(kHumanMl3dJointParents[j] < 0 ? "" : kHumanMl3dJointNames[kHumanMl3dJointParents[j]]);
  }
  const int64_t frames = array.shape[0];
  data.time_s.resize(static_cast<size_t>(frames));
  data.body_pose.assign(static_cast<size_t>(frames) * 22 * 7, std::nan(""));
  for (int64_t t = 0; t < frames; ++t) {
    data.time_s[static_cast<size_t>(t)] = static_cast<double>(t) / data.rate_hz;
    for (int j = 0; j < 22; ++j) {
      const double* source = &array.values[static_cast<size_t>((t * 22 + j) * 3)];
      double* pose = &data.body_pose[static_cast<size_t>((t * 22 + j) * 7)];
      pose[0] = source[0], pose[1] = source[1], pose[2] = source[2];
    }
  }
  data.metadata["npy"] = {{"dtype", array.dtype}, {"shape", array.shape}};
  return data;
}

MarkerData ReadHumanMl3dJoints(const std::string& path) {
  const std::vector<uint8_t> bytes = ReadFileBytes(path);
  return HumanMl3dJointsToMarkerData(ParseNpy(bytes.data(), bytes.size(), path), path);
}

}  // namespace syn
