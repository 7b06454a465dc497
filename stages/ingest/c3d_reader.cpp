#include "stages/ingest/c3d_reader.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <map>

#include <Eigen/Geometry>

#include "common/error.h"
#include "common/file_bytes.h"

namespace syn {
namespace {

constexpr size_t kBlock = 512;

enum class Processor { kIntel = 84, kDec = 85, kMips = 86 };

// Number decoding for one processor type. Branching happens once per value
// kind, not per sample: the hot loops below are instantiated per processor.
struct Numbers {
  Processor processor = Processor::kIntel;

  int16_t int16(const uint8_t* p) const {
    return processor == Processor::kMips ? static_cast<int16_t>((p[0] << 8) | p[1])
                                         : static_cast<int16_t>(p[0] | (p[1] << 8));
  }
  uint16_t uint16(const uint8_t* p) const { return static_cast<uint16_t>(int16(p)); }
  float float32(const uint8_t* p) const {
    uint8_t b[4];
    if (processor == Processor::kMips) {
      b[0] = p[3], b[1] = p[2], b[2] = p[1], b[3] = p[0];
    } else if (processor == Processor::kDec) {
      // VAX F-float: swap the 16-bit words, read as IEEE, divide by 4 (exponent bias 128 vs 127, hidden bit at 0.5).
      b[0] = p[2], b[1] = p[3], b[2] = p[0], b[3] = p[1];
    } else {
      std::memcpy(b, p, 4);
    }
    float value;
    std::memcpy(&value, b, 4);
    return processor == Processor::kDec ? value / 4.0f : value;
  }
};

struct Parameter {
  int type = 0;                  // -1 char, 1 byte, 2 int16, 4 float
  std::vector<int> dimensions;
  size_t count = 0;              // the product of the dimensions, checked against the file's size when read
  const uint8_t* data = nullptr;
  size_t data_size = 0;
  size_t offset = 0;
  bool locked = false;           // negative name length
  std::string description;
};

using Parameters = std::map<std::string, Parameter>;  // "GROUP:NAME"

std::string Upper(std::string text) {
  for (char& c : text) c = static_cast<char>(std::toupper(static_cast<unsigned char>(c)));
  return text;
}

std::string TrimRight(std::string text) {
  while (!text.empty() && (text.back() == ' ' || text.back() == '\0')) text.pop_back();
  size_t start = 0;
  while (start < text.size() && text[start] == ' ') ++start;
  return text.substr(start);
}

// One record of the parameter section: a group (negative id) or a parameter (positive id).
//   byte 0: name length (signed char; negative = "locked", the length is its absolute value)
//   byte 1: group id (signed char)
//   name, then int16 'offset to next' (processor byte order) counted from the offset's own first byte
//   parameters only: type (signed char: -1 char, 1 byte, 2 int16, 4 float), dimension count, dimensions (bytes)
//   data, then description length (byte) and description
struct Record {
  int group = 0;
  std::string name;
  bool locked = false;
  std::string description;
  size_t offset_at = 0;  // byte offset of 'offset to next'
  int next_offset = 0;
  bool parameter_ok = false;
  Parameter parameter;
};

enum class RecordRead { kRecord, kEnd, kRunsPast };

RecordRead ReadRecord(const uint8_t* bytes, size_t size, size_t position, size_t end, const Numbers& numbers,
                      Record* record) {
  const int name_length = std::abs(static_cast<int8_t>(bytes[position]));
  record->locked = static_cast<int8_t>(bytes[position]) < 0;
  record->group = static_cast<int8_t>(bytes[position + 1]);
  if (name_length == 0 || record->group == 0) return RecordRead::kEnd;
  const size_t name_at = position + 2;
  if (name_at + static_cast<size_t>(name_length) + 2 > end) return RecordRead::kRunsPast;
  record->name = Upper(std::string(reinterpret_cast<const char*>(bytes + name_at), static_cast<size_t>(name_length)));
  record->offset_at = name_at + static_cast<size_t>(name_length);
  record->next_offset = numbers.int16(bytes + record->offset_at);
  const size_t body = record->offset_at + 2;
  // Description: a length byte and that many characters, after the offset (groups) or the data (parameters),
  // within the record. OptiTrack Motive leaves both out: its next record starts right after the data.
  const size_t record_end = record->next_offset > 0 ? std::min(end, record->offset_at + static_cast<size_t>(record->next_offset)) : end;
  const auto read_description = [&](size_t at) {
    if (at + 1 > record_end) return;
    const size_t length = bytes[at];
    if (at + 1 + length <= record_end) record->description = TrimRight(std::string(reinterpret_cast<const char*>(bytes + at + 1), length));
  };
  if (record->group < 0) {
    read_description(body);
    return RecordRead::kRecord;
  }
  Parameter& parameter = record->parameter;
  parameter.offset = position;
  record->parameter_ok = false;
  if (body + 2 > end) return RecordRead::kRecord;
  parameter.type = static_cast<int8_t>(bytes[body]);
  const int dimension_count = bytes[body + 1];
  if ((parameter.type != -1 && parameter.type != 1 && parameter.type != 2 && parameter.type != 4) ||
      body + 2 + static_cast<size_t>(dimension_count) > end) {
    return RecordRead::kRecord;
  }
  // Up to 255 dimensions of up to 255 each: their product can pass any size_t, and a wrapped count would
  // pass the bounds check below while its values run past the file (a fuzzer's find). A product over the
  // file's size cannot fit anyway (a dimension of 0 makes it 0 whatever came before).
  bool count_fits = true;
  size_t elements = 1;
  for (int d = 0; d < dimension_count; ++d) {
    const size_t dimension = bytes[body + 2 + static_cast<size_t>(d)];
    parameter.dimensions.push_back(static_cast<int>(dimension));
    if (dimension == 0) {
      elements = 0, count_fits = true;
    } else if (elements > size / dimension) {
      count_fits = false;
    } else {
      elements *= dimension;
    }
  }
  parameter.data = bytes + body + 2 + dimension_count;
  parameter.count = count_fits ? elements : 0;
  parameter.data_size = parameter.count * static_cast<size_t>(std::abs(parameter.type));
  record->parameter_ok = count_fits && static_cast<size_t>(parameter.data - bytes) + parameter.data_size <= size;
  parameter.locked = record->locked;
  if (record->parameter_ok) read_description(static_cast<size_t>(parameter.data - bytes) + parameter.data_size);
  parameter.description = record->description;
  return RecordRead::kRecord;
}

// The section ends where the data begins (when the data comes after it), else at the end of the file.
// Its own block count (byte 3 of its 4-byte header: reserved, key 0x50, block count, processor) is a
// lower bound only: Qualisys writes one smaller than what it uses.
size_t ParameterSectionEnd(const uint8_t* bytes, size_t size, size_t start, size_t data_start) {
  const size_t blocks = bytes[start + 2];
  return std::min(size, std::max(start + std::max<size_t>(blocks, 1) * kBlock, data_start > start ? data_start : size));
}

// Parses the parameter section, following each record's "offset to next".
// A corrupt section ends the walk with a warning: what was read is kept.
struct Group {
  bool locked = false;
  std::string description;
};

Parameters ReadParameters(const uint8_t* bytes, size_t size, size_t start, size_t data_start, const Numbers& numbers,
                          std::vector<std::string>& warnings, std::map<std::string, Group>* groups = nullptr) {
  Parameters parameters;
  if (start + 4 > size) return parameters;
  const size_t end = ParameterSectionEnd(bytes, size, start, data_start);
  std::map<int, std::string> group_names;
  struct Pending {
    int group;
    std::string name;
    Parameter parameter;
  };
  std::vector<Pending> pending;
  size_t position = start + 4;
  for (int guard = 0; guard < 100000 && position + 2 <= end; ++guard) {
    Record record;
    const RecordRead read = ReadRecord(bytes, size, position, end, numbers, &record);
    if (read == RecordRead::kEnd) break;
    if (read == RecordRead::kRunsPast) {
      warnings.push_back("parameter section: record at byte offset " + std::to_string(position) +
                         " runs past the section; stopped reading parameters there");
      break;
    }
    if (record.group < 0) {
      group_names[-record.group] = record.name;
      if (groups) (*groups)[record.name] = {record.locked, record.description};
    } else if (record.parameter_ok) {
      pending.push_back({record.group, record.name, record.parameter});
    } else {
      warnings.push_back("parameter " + record.name + " at byte offset " + std::to_string(position) +
                         " is malformed or runs past the file; ignored");
    }
    if (record.next_offset <= 0) break;  // last record
    const size_t next = record.offset_at + static_cast<size_t>(record.next_offset);
    if (next <= position || next >= end) {
      warnings.push_back("parameter section: 'offset to next' at byte offset " + std::to_string(record.offset_at) +
                         " points outside the section; stopped reading parameters there");
      break;
    }
    position = next;
  }
  for (Pending& entry : pending) {
    const auto group = group_names.find(entry.group);
    if (group == group_names.end()) continue;
    parameters[group->second + ":" + entry.name] = entry.parameter;
  }
  return parameters;
}

const Parameter* Find(const Parameters& parameters, const std::string& key) {
  const auto found = parameters.find(key);
  return found == parameters.end() ? nullptr : &found->second;
}

double NumberAt(const Parameter& parameter, size_t index, const Numbers& numbers) {
  if (index >= parameter.count) return std::nan("");
  switch (parameter.type) {
    case 1: return parameter.data[index];
    case 2: return numbers.int16(parameter.data + 2 * index);
    case 4: return numbers.float32(parameter.data + 4 * index);
    default: return std::nan("");
  }
}

std::vector<double> Numbers_(const Parameters& parameters, const std::string& key, const Numbers& numbers) {
  std::vector<double> values;
  const Parameter* parameter = Find(parameters, key);
  if (!parameter || parameter->type == -1) return values;
  for (size_t i = 0; i < parameter->count; ++i) values.push_back(NumberAt(*parameter, i, numbers));
  return values;
}

// A count or block number read from a parameter (a float parameter can hold anything): negative or not finite
// is 0, and it saturates far above any real file, so the conversion is defined.
size_t Count(double value) { return value >= 1 ? static_cast<size_t>(std::min(value, 4.0e9)) : 0; }

// A parameter number as a 16-bit word: integer parameters are stored signed (65535 reads as -1); a float
// outside the word's range reads as 0.
size_t Word(double value) {
  return value >= -32768 && value <= 65535 ? static_cast<size_t>(static_cast<uint16_t>(static_cast<int>(value))) : 0;
}

double Number(const Parameters& parameters, const std::string& key, const Numbers& numbers, double fallback) {
  const Parameter* parameter = Find(parameters, key);
  if (!parameter || parameter->type == -1 || parameter->count == 0) return fallback;
  return NumberAt(*parameter, 0, numbers);
}

// A char parameter as strings: the first dimension is the string length.
std::vector<std::string> Strings(const Parameters& parameters, const std::string& key) {
  std::vector<std::string> strings;
  const Parameter* parameter = Find(parameters, key);
  if (!parameter || parameter->type != -1) return strings;
  if (parameter->dimensions.empty()) return strings;
  const size_t length = static_cast<size_t>(parameter->dimensions[0]);
  if (length == 0) return strings;
  const size_t count = parameter->count / length;
  for (size_t i = 0; i < count; ++i) {
    strings.push_back(TrimRight(std::string(reinterpret_cast<const char*>(parameter->data + i * length), length)));
  }
  return strings;
}

// LABELS, LABELS2, LABELS3 ... concatenated.
std::vector<std::string> ConcatenatedStrings(const Parameters& parameters, const std::string& group, const std::string& name) {
  std::vector<std::string> all = Strings(parameters, group + ":" + name);
  for (int k = 2; k < 100; ++k) {
    const std::string key = group + ":" + name + std::to_string(k);
    if (!Find(parameters, key)) break;
    const std::vector<std::string> more = Strings(parameters, key);
    all.insert(all.end(), more.begin(), more.end());
  }
  return all;
}

double UnitToMetres(const std::string& unit) {
  const std::string lower = Upper(unit);
  if (lower == "MM") return 0.001;
  if (lower == "CM") return 0.01;
  if (lower == "M") return 1.0;
  return 0.0;
}

nlohmann::json ParameterJson(const Parameter& parameter, const Parameters& parameters, const std::string& key,
                             const Numbers& numbers) {
  if (parameter.type == -1) return Strings(parameters, key);
  return Numbers_(parameters, key, numbers);
}

// The C3D rotation extension (Theia3D markerless): per frame and segment a 4×4
// pose matrix stored column-major as 16 floats plus one reliability value,
// from block ROTATION:DATA_START. Segments become bodies.
void ReadRotations(const uint8_t* bytes, size_t size, const Parameters& parameters, const Numbers& numbers,
                   size_t frames, MarkerData& data) {
  const double used = Number(parameters, "ROTATION:USED", numbers, 0);
  const double start_block = Number(parameters, "ROTATION:DATA_START", numbers, 0);
  if (!(used > 0) || !(start_block >= 2)) return;
  const size_t segments = static_cast<size_t>(used);
  const size_t start = (static_cast<size_t>(start_block) - 1) * kBlock;
  const size_t frame_bytes = segments * 17 * 4;
  if (start >= size) {
    data.warnings.push_back("ROTATION:DATA_START points past the end of the file; rotations ignored");
    return;
  }
  size_t rotation_frames = frames;
  if ((size - start) / frame_bytes < rotation_frames) {
    rotation_frames = (size - start) / frame_bytes;
    data.warnings.push_back("the rotation data holds " + std::to_string(rotation_frames) + " of " +
                            std::to_string(frames) + " frames (truncated)");
  }
  std::vector<std::string> labels = ConcatenatedStrings(parameters, "ROTATION", "LABELS");
  labels.resize(segments);
  for (size_t k = 0; k < segments; ++k) {
    if (labels[k].empty()) labels[k] = "Segment" + std::to_string(k + 1);
    data.bodies.push_back(labels[k]);
    data.body_parents.push_back("");
  }
  data.body_pose.assign(frames * segments * 7, std::nan(""));
  for (size_t t = 0; t < rotation_frames; ++t) {
    for (size_t k = 0; k < segments; ++k) {
      const uint8_t* v = bytes + start + t * frame_bytes + k * 17 * 4;
      Eigen::Matrix4d pose;
      for (int column = 0; column < 4; ++column) {
        for (int row = 0; row < 4; ++row) pose(row, column) = numbers.float32(v + 4 * (column * 4 + row));
      }
      if (!pose.allFinite()) continue;
      const Eigen::Quaterniond orientation(pose.topLeftCorner<3, 3>());
      double* out = &data.body_pose[(t * segments + k) * 7];
      out[0] = pose(0, 3), out[1] = pose(1, 3), out[2] = pose(2, 3);
      out[3] = orientation.w(), out[4] = orientation.x(), out[5] = orientation.y(), out[6] = orientation.z();
    }
  }
}

// ---- the steps of ParseC3d, in file order ----------------------------------

// The header block's fields (1-based word n sits at byte 2(n-1)); numbers in the processor's byte order.
struct Header {
  size_t points = 0;            // word 2
  size_t analog_per_frame = 0;  // word 3: analog samples per 3D frame, all channels
  size_t first_frame = 0;       // word 4
  size_t last_frame = 0;        // word 5
  float scale = 0;              // words 7-8: negative = float storage
  size_t data_block = 0;        // word 9
  float rate = 0;               // words 11-12
};

// Where the parameter section is and which processor wrote the file (byte 4 of the section: 83 + type).
// Without a parameter section (or a garbled one), guess Intel, the common case.
struct Layout {
  Numbers numbers;
  size_t parameter_start = 0;
  bool has_parameters = false;
};

Layout FindParameterSection(const uint8_t* bytes, size_t size, std::vector<std::string>& warnings) {
  Layout layout;
  const size_t parameter_block = bytes[0];
  layout.parameter_start = parameter_block >= 2 ? (parameter_block - 1) * kBlock : 0;
  layout.has_parameters = layout.parameter_start >= kBlock && layout.parameter_start + 4 <= size;
  if (!layout.has_parameters) {
    warnings.push_back("no parameter section: using the header only");
    return layout;
  }
  const int processor = bytes[layout.parameter_start + 3];
  if (processor == 84 || processor == 85 || processor == 86) {
    layout.numbers.processor = static_cast<Processor>(processor);
  } else {
    warnings.push_back("processor type byte " + std::to_string(processor) + " at byte offset " +
                       std::to_string(layout.parameter_start + 3) +
                       " is not 84/85/86: no parameter section; using the header only");
    layout.has_parameters = false;
  }
  return layout;
}

Header ReadHeader(const uint8_t* bytes, const Numbers& numbers) {
  const auto word = [&](int n) { return numbers.uint16(bytes + 2 * (n - 1)); };
  Header header;
  header.points = word(2);
  header.analog_per_frame = word(3);
  header.first_frame = word(4);
  header.last_frame = word(5);
  header.scale = numbers.float32(bytes + 12);
  header.data_block = word(9);
  header.rate = numbers.float32(bytes + 20);
  return header;
}

// How the point data is stored: the parameters where they are usable, else the header.
struct PointLayout {
  size_t points = 0;
  double scale = 0;  // negative: float storage
  bool floats = false;
  double rate = 0;
  size_t data_start = 0;  // byte offset of frame 0
};

template <typename Fail>
PointLayout ReadPointLayout(const Header& header, const Parameters& parameters, const Numbers& numbers, size_t size,
                            std::vector<std::string>& warnings, const Fail& fail) {
  PointLayout layout;
  const double used = Number(parameters, "POINT:USED", numbers, static_cast<double>(header.points));
  layout.points = Word(used);
  if (layout.points != header.points) {
    warnings.push_back("POINT:USED (" + std::to_string(layout.points) + ") differs from the header (" +
                       std::to_string(header.points) + "); using the header");
    layout.points = header.points;
  }
  layout.scale = Number(parameters, "POINT:SCALE", numbers, header.scale);
  if (!std::isfinite(layout.scale) || layout.scale == 0) layout.scale = header.scale;
  layout.floats = layout.scale < 0;
  layout.rate = Number(parameters, "POINT:RATE", numbers, header.rate);
  if (!(layout.rate > 0) || !std::isfinite(layout.rate)) layout.rate = header.rate;
  if (!(layout.rate > 0) || !std::isfinite(layout.rate)) throw fail(20, "no usable frame rate (header and POINT:RATE)");
  const size_t stated_block = Count(Number(parameters, "POINT:DATA_START", numbers, 0));
  if (stated_block >= 2 && stated_block != header.data_block) {
    warnings.push_back("POINT:DATA_START differs from the header; using the header");
  }
  const size_t data_block = header.data_block;
  if (data_block < 2) throw fail(16, "the header's data-start block (word 9) is " + std::to_string(data_block) + "; expected >= 2");
  layout.data_start = (data_block - 1) * kBlock;
  if (layout.data_start > size) {
    throw fail(16, "the data section starts at byte " + std::to_string(layout.data_start) + ", past the end of the file");
  }
  return layout;
}

// Analog channels and subframes per 3D frame; analog data the parameters cannot explain is dropped.
struct AnalogLayout {
  size_t channels = 0;
  size_t subframes = 0;
};

AnalogLayout ReadAnalogLayout(const Header& header, const Parameters& parameters, const Numbers& numbers,
                              std::vector<std::string>& warnings) {
  AnalogLayout layout;
  layout.channels = Count(Number(parameters, "ANALOG:USED", numbers, 0));
  if (layout.channels > 0 && header.analog_per_frame % layout.channels == 0) {
    layout.subframes = header.analog_per_frame / layout.channels;
  }
  if (layout.channels > 0 && layout.subframes == 0) {
    warnings.push_back("ANALOG:USED does not divide the header's analog samples per frame; analog data ignored");
    layout.channels = 0;
  }
  if (layout.channels == 0) layout.subframes = 0;
  return layout;
}

// Bytes per frame: the layout comes from the header alone (analog values we cannot interpret still
// take their place).
size_t FrameBytes(const Header& header, const PointLayout& points) {
  return (points.points * 4 + header.analog_per_frame) * (points.floats ? 4 : 2);
}

// Frames: header (16-bit), or TRIAL:ACTUAL_*_FIELD for long trials, or POINT:FRAMES; then what the file holds.
size_t CountFrames(const Header& header, const Parameters& parameters, const Numbers& numbers, const PointLayout& points,
                   size_t size, std::vector<std::string>& warnings) {
  size_t frames = header.last_frame >= header.first_frame ? header.last_frame - header.first_frame + 1 : 0;
  const std::vector<double> start_field = Numbers_(parameters, "TRIAL:ACTUAL_START_FIELD", numbers);
  const std::vector<double> end_field = Numbers_(parameters, "TRIAL:ACTUAL_END_FIELD", numbers);
  if (start_field.size() >= 2 && end_field.size() >= 2) {
    const auto field = [](const std::vector<double>& words) {
      return Word(words[0]) + (Word(words[1]) << 16);
    };
    const size_t first = field(start_field), last = field(end_field);
    if (last >= first && last - first + 1 > frames) frames = last - first + 1;
  }
  const double point_frames = Number(parameters, "POINT:FRAMES", numbers, -1);
  const size_t frame_bytes = FrameBytes(header, points);
  if (frame_bytes == 0) return frames;  // No points and no analog (Theia's ROTATION-only files): the header times the trial.
  const size_t available = (size - points.data_start) / frame_bytes;
  if (point_frames > 0) {
    const size_t stated = Word(point_frames);
    if (stated > frames && stated <= available) {
      warnings.push_back("header says " + std::to_string(frames) + " frames, POINT:FRAMES " + std::to_string(stated) +
                         ", and the file holds them: using " + std::to_string(stated));
      frames = stated;
    } else if (stated > frames) {
      // c3d.org sample13 (Dance): header 499, POINT:FRAMES 500, and the file holds exactly 499.
      warnings.push_back("POINT:FRAMES says " + std::to_string(stated) + " but the file holds " +
                         std::to_string(std::min(available, frames)) + " frames, as the header says: using the header");
    }
  }
  if (available < frames) {
    warnings.push_back("the data section holds " + std::to_string(available) + " complete frames of the " +
                       std::to_string(frames) + " declared (truncated file); reading those");
    frames = available;
  }
  return frames;
}

// POINT:UNITS (length unit) and POINT:Y_SCREEN (the up axis; Z when absent).
void ReadUnitsAndAxis(const Parameters& parameters, MarkerData& data) {
  const std::vector<std::string> units = Strings(parameters, "POINT:UNITS");
  data.length_unit_to_m = 0.001;
  if (!units.empty()) {
    const double unit = UnitToMetres(units[0]);
    if (unit > 0) data.length_unit_to_m = unit;
    else data.warnings.push_back("POINT:UNITS '" + units[0] + "' is not mm, cm or m; assuming mm");
    for (const std::string& other : units) {
      if (UnitToMetres(other) != UnitToMetres(units[0])) {
        data.warnings.push_back("POINT:UNITS lists different units per point; using '" + units[0] + "'");
        break;
      }
    }
  }
  const std::vector<std::string> y_screen = Strings(parameters, "POINT:Y_SCREEN");
  data.up_axis = 'z';
  if (!y_screen.empty() && y_screen[0].size() == 2) {
    const char axis = static_cast<char>(std::tolower(static_cast<unsigned char>(y_screen[0][1])));
    if (axis == 'x' || axis == 'y' || axis == 'z') data.up_axis = axis;
  }
}

// Where each stored point goes: markers to data.labels / points, computed points (angles, forces ...)
// to data.computed_labels / computed_points.
struct PointSlots {
  std::vector<size_t> destination;  // slot of each stored point in points / computed_points
  std::vector<bool> is_computed;
};

PointSlots SortPoints(const Parameters& parameters, size_t points, MarkerData& data) {
  std::vector<std::string> labels = ConcatenatedStrings(parameters, "POINT", "LABELS");
  labels.resize(points);
  for (size_t i = 0; i < points; ++i) {
    if (labels[i].empty()) labels[i] = "Point" + std::to_string(i + 1);
  }
  std::map<std::string, std::string> computed_kind;
  for (const auto& [group_key, kind] : std::vector<std::pair<std::string, std::string>>{
           {"ANGLES", "angle"}, {"FORCES", "force"}, {"MOMENTS", "moment"}, {"POWERS", "power"},
           {"SCALARS", "scalar"}, {"REACTIONS", "reaction"}}) {
    for (const std::string& label : ConcatenatedStrings(parameters, "POINT", group_key)) computed_kind[label] = kind;
  }
  PointSlots slots;
  slots.destination.resize(points);
  slots.is_computed.assign(points, false);
  for (size_t i = 0; i < points; ++i) {
    const auto kind = computed_kind.find(labels[i]);
    if (kind != computed_kind.end() && !labels[i].empty()) {
      slots.destination[i] = data.computed_labels.size();
      slots.is_computed[i] = true;
      data.computed_labels.push_back(labels[i]);
      data.computed_kinds.push_back(kind->second);
    } else {
      slots.destination[i] = data.labels.size();
      data.labels.push_back(labels[i]);
    }
  }
  return slots;
}

// Analog labels, units and the scaling raw -> physical: (raw - offset) * scale * general scale.
struct AnalogScaling {
  std::vector<double> scale, offset;
  double general_scale = 1.0;
  bool unsigned_values = false;
};

AnalogScaling ReadAnalogChannels(const Parameters& parameters, const Numbers& numbers, const AnalogLayout& analog,
                                 double rate, MarkerData& data) {
  AnalogScaling scaling;
  std::vector<std::string> analog_labels = ConcatenatedStrings(parameters, "ANALOG", "LABELS");
  std::vector<std::string> analog_units = ConcatenatedStrings(parameters, "ANALOG", "UNITS");
  scaling.scale = Numbers_(parameters, "ANALOG:SCALE", numbers);
  scaling.offset = Numbers_(parameters, "ANALOG:OFFSET", numbers);
  for (int k = 2; k < 10; ++k) {
    const std::vector<double> more_scale = Numbers_(parameters, "ANALOG:SCALE" + std::to_string(k), numbers);
    scaling.scale.insert(scaling.scale.end(), more_scale.begin(), more_scale.end());
    const std::vector<double> more_offset = Numbers_(parameters, "ANALOG:OFFSET" + std::to_string(k), numbers);
    scaling.offset.insert(scaling.offset.end(), more_offset.begin(), more_offset.end());
  }
  scaling.general_scale = Number(parameters, "ANALOG:GEN_SCALE", numbers, 1.0);
  const std::vector<std::string> analog_format = Strings(parameters, "ANALOG:FORMAT");
  scaling.unsigned_values = !analog_format.empty() && Upper(analog_format[0]) == "UNSIGNED";
  if (analog.channels == 0) return scaling;
  analog_labels.resize(analog.channels);
  analog_units.resize(analog.channels);
  for (size_t c = 0; c < analog.channels; ++c) {
    if (analog_labels[c].empty()) analog_labels[c] = "Channel" + std::to_string(c + 1);
  }
  scaling.scale.resize(analog.channels, 1.0);
  scaling.offset.resize(analog.channels, 0.0);
  for (double& offset : scaling.offset) {
    if (scaling.unsigned_values && offset < 0) offset += 65536.0;
  }
  data.analog_labels = analog_labels;
  data.analog_units = analog_units;
  data.analog_rate_hz = rate * static_cast<double>(analog.subframes);
  return scaling;
}

// The data section: one tight loop over frames, points, then analog subframes.
void ReadFrames(const uint8_t* bytes, const Numbers& numbers, const Header& header, const PointLayout& layout,
                const AnalogLayout& analog, const AnalogScaling& scaling, const PointSlots& slots, size_t frames,
                MarkerData& data) {
  const size_t points = layout.points;
  const size_t markers = data.labels.size();
  const size_t computed = data.computed_labels.size();
  const size_t value_bytes = layout.floats ? 4 : 2;
  const size_t frame_bytes = FrameBytes(header, layout);
  data.time_s.resize(frames);
  data.points.assign(frames * markers * 3, std::nan(""));
  data.computed_points.assign(frames * computed * 3, std::nan(""));
  data.analog.assign(frames * analog.subframes * analog.channels, 0.0);
  const double integer_scale = std::abs(layout.scale);
  for (size_t t = 0; t < frames; ++t) {
    data.time_s[t] = static_cast<double>(t) / layout.rate;
    const uint8_t* frame = bytes + layout.data_start + t * frame_bytes;
    for (size_t p = 0; p < points; ++p) {
      double x, y, z;
      bool valid;
      if (layout.floats) {
        const uint8_t* v = frame + p * 16;
        x = numbers.float32(v), y = numbers.float32(v + 4), z = numbers.float32(v + 8);
        const float residual = numbers.float32(v + 12);
        valid = residual >= 0 && std::isfinite(x) && std::isfinite(y) && std::isfinite(z);
      } else {
        const uint8_t* v = frame + p * 8;
        x = numbers.int16(v) * integer_scale, y = numbers.int16(v + 2) * integer_scale, z = numbers.int16(v + 4) * integer_scale;
        valid = numbers.int16(v + 6) >= 0;
      }
      if (x == 0 && y == 0 && z == 0) valid = false;
      if (!valid) continue;
      double* out = slots.is_computed[p] ? &data.computed_points[(t * computed + slots.destination[p]) * 3]
                                         : &data.points[(t * markers + slots.destination[p]) * 3];
      out[0] = x, out[1] = y, out[2] = z;
    }
    const uint8_t* samples = frame + points * 4 * value_bytes;
    for (size_t s = 0; s < analog.subframes; ++s) {
      for (size_t c = 0; c < analog.channels; ++c) {
        const uint8_t* v = samples + (s * analog.channels + c) * value_bytes;
        const double raw = layout.floats ? numbers.float32(v)
                                         : (scaling.unsigned_values ? numbers.uint16(v) : numbers.int16(v));
        data.analog[(t * analog.subframes + s) * analog.channels + c] =
            (raw - scaling.offset[c]) * scaling.scale[c] * scaling.general_scale;
      }
    }
  }
}

// Events: the EVENT group (times are minutes, seconds pairs); else the header's event section (words
// 150-234: key 12345, count, up to 18 times as float seconds and 4-character labels).
void ReadEvents(const uint8_t* bytes, const Parameters& parameters, const Numbers& numbers, MarkerData& data) {
  const std::vector<std::string> event_labels = Strings(parameters, "EVENT:LABELS");
  const std::vector<std::string> event_contexts = Strings(parameters, "EVENT:CONTEXTS");
  const std::vector<double> event_times = Numbers_(parameters, "EVENT:TIMES", numbers);
  const size_t event_count = std::min<size_t>(event_labels.size(), event_times.size() / 2);
  for (size_t e = 0; e < event_count; ++e) {
    data.events.push_back({event_labels[e], e < event_contexts.size() ? event_contexts[e] : "",
                           event_times[2 * e] * 60.0 + event_times[2 * e + 1]});
  }
  if (!data.events.empty() || numbers.uint16(bytes + 298) != 12345) return;
  const size_t header_events = std::min<size_t>(numbers.uint16(bytes + 300), 18);
  for (size_t e = 0; e < header_events; ++e) {
    const double time = numbers.float32(bytes + 304 + 4 * e);
    const std::string label = TrimRight(std::string(reinterpret_cast<const char*>(bytes + 396 + 4 * e), 4));
    if (std::isfinite(time)) data.events.push_back({label, "header", time});
  }
}

// Facts worth keeping: storage, the header's frame numbers, and whole parameter groups users ask for.
void RecordMetadata(const Numbers& numbers, const Header& header, const PointLayout& layout,
                    const Parameters& parameters, MarkerData& data) {
  nlohmann::json& meta = data.metadata["c3d"];
  meta["processor"] = numbers.processor == Processor::kIntel ? "intel" : numbers.processor == Processor::kDec ? "dec" : "mips";
  meta["storage"] = layout.floats ? "float" : "int16";
  meta["scale"] = layout.scale;
  meta["header_first_frame"] = header.first_frame;
  meta["header_last_frame"] = header.last_frame;
  meta["points_in_file"] = layout.points;
  for (const char* group : {"FORCE_PLATFORM", "SUBJECTS", "MANUFACTURER", "ROTATION"}) {
    for (const auto& [key, parameter] : parameters) {
      if (key.rfind(std::string(group) + ":", 0) == 0) {
        meta[group][key.substr(std::strlen(group) + 1)] = ParameterJson(parameter, parameters, key, numbers);
      }
    }
  }
}

}  // namespace

MarkerData ParseC3d(const uint8_t* bytes, size_t size, const std::string& source_name) {
  const auto fail = [&](size_t offset, const std::string& message) {
    return DataError(Location::AtByte(source_name, static_cast<int64_t>(offset)), message);
  };
  if (size < kBlock) throw fail(0, "a C3D file has at least one 512-byte header block; this one has " + std::to_string(size) + " bytes");
  if (bytes[1] != 0x50 && bytes[0] < 2) throw fail(1, "not a C3D file: expected the key byte 0x50 at offset 1");
  MarkerData data;
  const Layout layout = FindParameterSection(bytes, size, data.warnings);
  const Numbers& numbers = layout.numbers;
  const Header header = ReadHeader(bytes, numbers);
  Parameters parameters;
  if (layout.has_parameters) {
    parameters = ReadParameters(bytes, size, layout.parameter_start,
                                header.data_block >= 2 ? (header.data_block - 1) * kBlock : 0, numbers, data.warnings);
  }
  const PointLayout point_layout = ReadPointLayout(header, parameters, numbers, size, data.warnings, fail);
  data.rate_hz = point_layout.rate;
  const AnalogLayout analog = ReadAnalogLayout(header, parameters, numbers, data.warnings);
  const size_t frames = CountFrames(header, parameters, numbers, point_layout, size, data.warnings);
  const PointSlots slots = SortPoints(parameters, point_layout.points, data);
  ReadUnitsAndAxis(parameters, data);
  const AnalogScaling scaling = ReadAnalogChannels(parameters, numbers, analog, point_layout.rate, data);
  ReadFrames(bytes, numbers, header, point_layout, analog, scaling, slots, frames, data);
  ReadEvents(bytes, parameters, numbers, data);
  RecordMetadata(numbers, header, point_layout, parameters, data);
  ReadRotations(bytes, size, parameters, numbers, frames, data);
  return data;
}

std::vector<C3dParameter> ParseC3dParameters(const uint8_t* bytes, size_t size, const std::string& source_name) {
  if (size < kBlock) {
    throw DataError(Location::AtByte(source_name, 0), "a C3D file has at least one 512-byte header block");
  }
  std::vector<std::string> warnings;
  const Layout layout = FindParameterSection(bytes, size, warnings);
  std::vector<C3dParameter> result;
  if (!layout.has_parameters) return result;
  const Header header = ReadHeader(bytes, layout.numbers);
  std::map<std::string, Group> groups;
  const Parameters parameters = ReadParameters(bytes, size, layout.parameter_start,
                                               header.data_block >= 2 ? (header.data_block - 1) * kBlock : 0,
                                               layout.numbers, warnings, &groups);
  for (const auto& [name, group] : groups) {
    C3dParameter entry;
    entry.key = name + ":";
    entry.locked = group.locked;
    entry.description = group.description;
    result.push_back(entry);
  }
  for (const auto& [key, parameter] : parameters) {
    C3dParameter entry;
    entry.key = key;
    entry.type = parameter.type;
    entry.dimensions = parameter.dimensions;
    entry.locked = parameter.locked;
    entry.description = parameter.description;
    if (parameter.type == -1) entry.strings = Strings(parameters, key);
    else entry.numbers = Numbers_(parameters, key, layout.numbers);
    result.push_back(entry);
  }
  std::sort(result.begin(), result.end(), [](const C3dParameter& a, const C3dParameter& b) { return a.key < b.key; });
  return result;
}

MarkerData ReadC3d(const std::string& path) {
  const std::vector<uint8_t> bytes = ReadFileBytes(path);
  return ParseC3d(bytes.data(), bytes.size(), path);
}

}  // namespace syn
