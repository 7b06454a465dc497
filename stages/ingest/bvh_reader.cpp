#include "stages/ingest/bvh_reader.h"

#include <algorithm>

#include <charconv>
#include <cmath>

#include <Eigen/Geometry>

#include "common/error.h"
#include "common/file_bytes.h"

namespace syn {
namespace {

enum class Channel { kXposition, kYposition, kZposition, kXrotation, kYrotation, kZrotation };

struct BvhJoint {
  std::string name;
  int parent = -1;
  Eigen::Vector3d offset = Eigen::Vector3d::Zero();
  std::vector<Channel> channels;
  int first_channel = 0;  // index of its first value in a frame line
  bool end_site = false;
};

// Splits the text into whitespace-separated tokens, remembering each one's line.
class Tokens {
 public:
  Tokens(std::string_view text, std::string source) : text_(text), source_(std::move(source)) {}

  bool next(std::string_view* token) {
    while (position_ < text_.size() && std::isspace(static_cast<unsigned char>(text_[position_]))) {
      if (text_[position_] == '\n') ++line_;
      ++position_;
    }
    if (position_ >= text_.size()) return false;
    const size_t start = position_;
    while (position_ < text_.size() && !std::isspace(static_cast<unsigned char>(text_[position_]))) ++position_;
    *token = text_.substr(start, position_ - start);
    return true;
  }

  std::string_view expectAny(const char* what) {
    std::string_view token;
    if (!next(&token)) fail(std::string("unexpected end of file; expected ") + what);
    return token;
  }

  void expect(std::string_view wanted) {
    const std::string_view token = expectAny(std::string(wanted).c_str());
    if (token != wanted) fail("expected '" + std::string(wanted) + "', found '" + std::string(token) + "'");
  }

  double number(const char* what) {
    const std::string_view token = expectAny(what);
    return parseNumber(token, what);
  }

  double parseNumber(std::string_view token, const char* what) const {
    double value = 0;
    const char* begin = token.data();
    if (!token.empty() && token.front() == '+') ++begin;
    const auto [end, error] = std::from_chars(begin, token.data() + token.size(), value);
    if (error != std::errc() || end != token.data() + token.size() || !std::isfinite(value)) {
      fail("expected " + std::string(what) + ", found '" + std::string(token) + "'");
    }
    return value;
  }

  // The rest of the text from the current position, and its line number.
  std::string_view rest() const { return text_.substr(position_); }
  int64_t line() const { return line_; }

  [[noreturn]] void fail(const std::string& message) const {
    throw DataError(Location::AtLine(source_, line_), message);
  }

 private:
  std::string_view text_;
  std::string source_;
  size_t position_ = 0;
  int64_t line_ = 1;
};

Channel ParseChannel(std::string_view token, const Tokens& tokens) {
  if (token == "Xposition") return Channel::kXposition;
  if (token == "Yposition") return Channel::kYposition;
  if (token == "Zposition") return Channel::kZposition;
  if (token == "Xrotation") return Channel::kXrotation;
  if (token == "Yrotation") return Channel::kYrotation;
  if (token == "Zrotation") return Channel::kZrotation;
  tokens.fail("unknown channel '" + std::string(token) + "' (expected X/Y/Z position or rotation)");
}

// Reads "{ OFFSET ... [CHANNELS ...] (JOINT ... | End Site ...)* }" for joint `index`.
void ParseJointBody(Tokens& tokens, std::vector<BvhJoint>& joints, int index, int& channel_count) {
  tokens.expect("{");
  tokens.expect("OFFSET");
  Eigen::Vector3d offset;
  for (int i = 0; i < 3; ++i) offset[i] = tokens.number("an OFFSET value");
  joints[static_cast<size_t>(index)].offset = offset;
  if (joints[static_cast<size_t>(index)].end_site) {
    tokens.expect("}");
    return;
  }
  // The format gives every ROOT and JOINT a CHANNELS line; a joint with none would be an End Site. Holding
  // to that keeps the bodies posed per frame within twice the values a frame line carries (each joint has a
  // channel, each End Site a joint of its own), so a reader's work grows with the file, not past it.
  tokens.expect("CHANNELS");
  const double count = tokens.number("a channel count");
  if (count < 1 || count > 6 || count != std::floor(count)) tokens.fail("a joint has 1 to 6 channels");
  joints[static_cast<size_t>(index)].first_channel = channel_count;
  for (int i = 0; i < static_cast<int>(count); ++i) {
    joints[static_cast<size_t>(index)].channels.push_back(ParseChannel(tokens.expectAny("a channel name"), tokens));
  }
  channel_count += static_cast<int>(count);
  std::string_view token = tokens.expectAny("JOINT, End or }");
  bool has_end_site = false;
  while (token != "}") {
    BvhJoint child;
    child.parent = index;
    if (token == "JOINT") {
      child.name = std::string(tokens.expectAny("a joint name"));
    } else if (token == "End") {
      tokens.expect("Site");
      // Its body is named after the joint: a second one would be a second body of the same name.
      if (has_end_site) tokens.fail("a joint has at most one End Site");
      has_end_site = true;
      child.end_site = true;
      child.name = joints[static_cast<size_t>(index)].name + "_end";
    } else {
      tokens.fail("expected JOINT, End Site or }, found '" + std::string(token) + "'");
    }
    if (joints.size() > 100000) tokens.fail("too many joints");
    joints.push_back(child);
    ParseJointBody(tokens, joints, static_cast<int>(joints.size()) - 1, channel_count);
    token = tokens.expectAny("JOINT, End or }");
  }
}

Eigen::Matrix3d AxisRotation(Channel channel, double degrees) {
  const double radians = degrees * M_PI / 180.0;
  const Eigen::Vector3d axis = channel == Channel::kXrotation   ? Eigen::Vector3d::UnitX()
                               : channel == Channel::kYrotation ? Eigen::Vector3d::UnitY()
                                                                : Eigen::Vector3d::UnitZ();
  return Eigen::AngleAxisd(radians, axis).toRotationMatrix();
}

// Standing height of the rest pose (all channels zero): vertical (Y) extent of every joint and end site.
double RestHeight(const std::vector<BvhJoint>& joints) {
  std::vector<Eigen::Vector3d> world(joints.size());
  double low = INFINITY, high = -INFINITY;
  for (size_t j = 0; j < joints.size(); ++j) {
    world[j] = joints[j].parent < 0 ? joints[j].offset : world[static_cast<size_t>(joints[j].parent)] + joints[j].offset;
    low = std::min(low, world[j].y());
    high = std::max(high, world[j].y());
  }
  return high - low;
}

// The converter's ease-in (BvhOptions::drop_first_frame): from `first`, the first frame after the rest frame,
// how many frames are still on their way from the rest pose into the take. Their steps (root-mean-square over
// the rotation channels, across ±180°) are a run of at least kEaseInRun frames each over kEaseInStepRatio times
// the take's median step and over kEaseInSpeed: CMU's lawrennd, Przestr and papagina copies step 400-800 °/s
// for 3-5 frames where their takes' medians are 13-98 °/s. A take that starts at once keeps its frames: cgspeed's
// conversions (frame 1 already 17-35° from the T-pose) step at most once that fast (CMU 05_01: 269 °/s, then
// 102), a dance's fast start does not stand out from its median. At most kEaseInSeconds are dropped.
constexpr double kEaseInStepRatio = 4.0;
constexpr double kEaseInSpeed = 200.0;  // °/s
constexpr int64_t kEaseInRun = 2;
constexpr double kEaseInSeconds = 0.25;

int64_t EaseInEnd(const std::vector<double>& values, const std::vector<BvhJoint>& joints, int channel_count,
                  int64_t frames, int64_t first, double frame_time) {
  std::vector<int> rotation;
  for (const BvhJoint& joint : joints) {
    for (size_t c = 0; c < joint.channels.size(); ++c) {
      if (joint.channels[c] >= Channel::kXrotation) rotation.push_back(joint.first_channel + static_cast<int>(c));
    }
  }
  if (rotation.empty() || first < 1 || frames - first < 3) return first;
  // °/s: the RMS step of the rotation channels from frame k - 1 to k.
  const auto speed = [&](int64_t k) {
    const double* before = &values[static_cast<size_t>(k - 1) * static_cast<size_t>(channel_count)];
    const double* after = &values[static_cast<size_t>(k) * static_cast<size_t>(channel_count)];
    double sum = 0.0;
    for (const int c : rotation) {
      const double d = std::remainder(after[c] - before[c], 360.0);
      sum += d * d;
    }
    return std::sqrt(sum / static_cast<double>(rotation.size())) / frame_time;
  };
  std::vector<double> speeds;
  for (int64_t k = first + 1; k < frames; ++k) speeds.push_back(speed(k));
  std::nth_element(speeds.begin(), speeds.begin() + static_cast<std::ptrdiff_t>(speeds.size() / 2), speeds.end());
  const double threshold = std::max(kEaseInStepRatio * speeds[speeds.size() / 2], kEaseInSpeed);
  const int64_t last = std::min(frames - 2, first + static_cast<int64_t>(std::lround(kEaseInSeconds / frame_time)));
  int64_t run = 0;
  while (first + run < last && speed(first + run + 1) > threshold) ++run;
  return run >= kEaseInRun ? first + run : first;
}

// A teleport in the take's first kLeadInSeconds (BvhOptions::drop_first_frame): a joint that moves more than
// kTeleportSpeed rest-pose sizes (the rest pose's largest extent, a standing subject's height) per second
// between two frames ends a lead-in that is not the take. CMU 03_02 holds its T-pose arms for 50 frames while
// its legs walk (its whole body also jumps 11 cm at frame 24), then its hands jump 69 cm in one frame
// (64 statures/s): retargeted, the robot's arms snapped there, and the simulated G1 in paper mode, its arm
// torques at their limits, spun a shoulder through 378°. The other 50 CMU takes of the shared data move at
// most 15 statures/s in their first 0.5 s (a hand's 15 m/s is about 9).
constexpr double kLeadInSeconds = 0.5;
constexpr double kTeleportSpeed = 50.0;  // rest-pose sizes per second

// The rest pose's largest extent along any axis, in file units.
double RestSize(const std::vector<BvhJoint>& joints) {
  std::vector<Eigen::Vector3d> world(joints.size());
  Eigen::Vector3d low = Eigen::Vector3d::Constant(INFINITY), high = Eigen::Vector3d::Constant(-INFINITY);
  for (size_t j = 0; j < joints.size(); ++j) {
    world[j] = joints[j].parent < 0 ? joints[j].offset : world[static_cast<size_t>(joints[j].parent)] + joints[j].offset;
    low = low.cwiseMin(world[j]);
    high = high.cwiseMax(world[j]);
  }
  return (high - low).maxCoeff();
}

// A held lead-in (BvhOptions::drop_first_frame): from `first`, frames repeating one pose exactly, every
// channel, before the take moves. CMU 08_07 repeats one frame 6 times (0.05 s), then its hips jump 9 cm in
// 1/120 s, where they move 1.4 cm a frame after. No capture at its own rate repeats a frame bit for bit: the
// run is a hold, and it goes with its last frame (the take starts where the motion does). It takes at least
// kHoldRepeats repeats (a pair can repeat by chance where a file rounds its channels), and a take still
// holding after `lead_frames` (a static trial) is kept whole. Returns the take's first frame.
constexpr int64_t kHoldRepeats = 3;

int64_t HeldLeadInEnd(const std::vector<double>& values, int channel_count, int64_t frames, int64_t first,
                      int64_t lead_frames) {
  const auto repeats_next = [&](int64_t frame) {
    const double* row = &values[static_cast<size_t>(frame) * static_cast<size_t>(channel_count)];
    return std::equal(row, row + channel_count, row + channel_count);
  };
  const int64_t limit = std::min(frames - 2, first + lead_frames);
  int64_t end = first;
  while (end < limit && repeats_next(end)) ++end;
  return end - first >= kHoldRepeats && end < limit ? end + 1 : first;
}

}  // namespace

MarkerData ParseBvh(std::string_view text, const std::string& source_name, const BvhOptions& options) {
  Tokens tokens(text, source_name);
  tokens.expect("HIERARCHY");
  tokens.expect("ROOT");
  std::vector<BvhJoint> joints(1);
  joints[0].name = std::string(tokens.expectAny("the root joint's name"));
  int channel_count = 0;
  ParseJointBody(tokens, joints, 0, channel_count);
  std::string_view token = tokens.expectAny("MOTION");
  if (token == "ROOT") tokens.fail("several ROOT hierarchies are not supported");
  if (token != "MOTION") tokens.fail("expected MOTION, found '" + std::string(token) + "'");
  tokens.expect("Frames:");
  const double declared_frames = tokens.number("the frame count");
  if (!(declared_frames >= 0 && declared_frames <= 1e15) || declared_frames != std::floor(declared_frames)) {
    tokens.fail("the frame count must be a whole number of a plausible size");
  }
  tokens.expect("Frame");
  tokens.expect("Time:");
  const double frame_time = tokens.number("the frame time in seconds");
  if (!(frame_time > 0)) tokens.fail("Frame Time must be positive");

  // Frame lines: exactly channel_count numbers each. Skip the rest of the "Frame Time" line first.
  std::string_view rest = tokens.rest();
  int64_t line = tokens.line();
  const size_t first_newline = rest.find('\n');
  rest = first_newline == std::string_view::npos ? std::string_view() : rest.substr(first_newline + 1);
  ++line;
  const int64_t frames_wanted = static_cast<int64_t>(declared_frames);
  // Each value needs at least 2 bytes ("0 "): refuse counts the text cannot hold before allocating.
  if (frames_wanted > static_cast<int64_t>(rest.size() / (2 * static_cast<size_t>(channel_count))) + 1) {
    throw DataError(Location::AtLine(source_name, line),
                    "the header declares " + std::to_string(frames_wanted) + " frames but the file is too short for them");
  }
  std::vector<double> values(static_cast<size_t>(frames_wanted) * static_cast<size_t>(channel_count));
  int64_t frames_read = 0;
  while (frames_read < frames_wanted) {
    if (rest.empty()) {
      throw DataError(Location::AtLine(source_name, line),
                      "the file ends after " + std::to_string(frames_read) + " of the " + std::to_string(frames_wanted) +
                          " frames the header declares");
    }
    const size_t newline = rest.find('\n');
    std::string_view row = rest.substr(0, newline);
    rest = newline == std::string_view::npos ? std::string_view() : rest.substr(newline + 1);
    double* out = &values[static_cast<size_t>(frames_read) * static_cast<size_t>(channel_count)];
    int count = 0;
    size_t cursor = 0;
    while (true) {
      while (cursor < row.size() && std::isspace(static_cast<unsigned char>(row[cursor]))) ++cursor;
      if (cursor >= row.size()) break;
      size_t end = cursor;
      while (end < row.size() && !std::isspace(static_cast<unsigned char>(row[end]))) ++end;
      if (count >= channel_count) {
        throw DataError(Location::AtLine(source_name, line),
                        "frame " + std::to_string(frames_read) + " has more than the " + std::to_string(channel_count) +
                            " values the hierarchy declares");
      }
      const std::string_view number = row.substr(cursor, end - cursor);
      const char* begin = number.data() + (number.front() == '+' ? 1 : 0);
      const auto [parsed_end, error] = std::from_chars(begin, number.data() + number.size(), out[count]);
      if (error != std::errc() || parsed_end != number.data() + number.size()) {
        throw DataError(Location::AtLine(source_name, line),
                        "expected a number in frame " + std::to_string(frames_read) + ", found '" + std::string(number) + "'");
      }
      ++count;
      cursor = end;
    }
    if (count == 0) {  // blank line between frames
      ++line;
      continue;
    }
    if (count != channel_count) {
      throw DataError(Location::AtLine(source_name, line), "frame " + std::to_string(frames_read) + " has " +
                                                               std::to_string(count) + " values; the hierarchy declares " +
                                                               std::to_string(channel_count));
    }
    ++frames_read;
    ++line;
  }

  MarkerData data;
  data.rate_hz = 1.0 / frame_time;
  data.up_axis = 'y';
  data.length_unit_to_m = 1.0;  // unknown: the caller decides (GuessBvhScaleToMetres or --bvh-scale)
  for (const BvhJoint& joint : joints) {
    data.bodies.push_back(joint.name);
    data.body_parents.push_back(joint.parent < 0 ? "" : joints[static_cast<size_t>(joint.parent)].name);
  }
  if (options.drop_first_frame && frames_read == 1) {
    throw DataError(Location::InFile(source_name),
                    "the file's only frame is the reference frame that dropping the first frame removes: no frame is left");
  }
  int64_t first = options.drop_first_frame && frames_read > 0 ? 1 : 0;
  // Some of those conversions carry a second reference frame after the first, every channel exactly zero
  // (CMU 07_12: the skeleton at the origin, 40 cm from where the take starts): not part of the take either.
  const auto all_zero = [&](int64_t frame) {
    const double* row = &values[static_cast<size_t>(frame) * static_cast<size_t>(channel_count)];
    return std::all_of(row, row + channel_count, [](double value) { return value == 0.0; });
  };
  while (first > 0 && first + 1 < frames_read && all_zero(first)) ++first;
  // And others leave a joint on the rest pose for one frame more: every rotation channel of that joint
  // exactly zero, the next frame turning it (cgspeed's CMU 05_01: the right ankle, whose foot then turns
  // 22° in 1/120 s against 5° a frame after; 08_04's left ankle, 03_01's right knee). Those frames are not
  // part of the take either; a joint that stays at zero (a finger no one captured) is no sign.
  const auto joint_left_at_rest = [&](int64_t frame) {
    const double* row = &values[static_cast<size_t>(frame) * static_cast<size_t>(channel_count)];
    const double* next = row + channel_count;
    for (const BvhJoint& joint : joints) {
      bool at_rest = false, moves_next = false;
      for (size_t c = 0; c < joint.channels.size(); ++c) {
        if (joint.channels[c] < Channel::kXrotation) continue;
        const int index = joint.first_channel + static_cast<int>(c);
        if (row[index] != 0.0) {
          at_rest = false;
          break;
        }
        at_rest = true;
        moves_next = moves_next || next[index] != 0.0;
      }
      if (at_rest && moves_next) return true;
    }
    return false;
  };
  while (first > 0 && first + 1 < frames_read && joint_left_at_rest(first)) ++first;
  // And some hold the take's first pose for several frames before it moves (HeldLeadInEnd).
  const int64_t lead_frames = std::lround(kLeadInSeconds / frame_time);
  const int64_t before_hold = first;
  if (first > 0) first = HeldLeadInEnd(values, channel_count, frames_read, first, lead_frames);
  // Others ease in from it over a few frames (the lawrennd, Przestr and papagina copies of CMU: 4-5 frames,
  // 2° to 13-25° RMS from the rest pose), the hands sweeping 18 cm in 17 ms: a start no body makes, and one
  // that led the retargeted G1 of CMU 12_02 into a crouch it then kept the whole take (pelvis 10 cm under
  // its target, P1 median 47 mm; 30 mm without those frames).
  const int64_t after_reference = first;
  if (first > 0) first = EaseInEnd(values, joints, channel_count, frames_read, first, frame_time);
  std::vector<Eigen::Isometry3d> world(joints.size());
  // Every joint's pose in frame `row` of the file, into poses[B, 7].
  const auto pose_joints = [&](int64_t row_index, double* poses) {
    const double* row = &values[static_cast<size_t>(row_index) * static_cast<size_t>(channel_count)];
    for (size_t j = 0; j < joints.size(); ++j) {
      const BvhJoint& joint = joints[j];
      Eigen::Vector3d translation = joint.offset;
      Eigen::Matrix3d rotation = Eigen::Matrix3d::Identity();
      for (size_t c = 0; c < joint.channels.size(); ++c) {
        const double value = row[joint.first_channel + static_cast<int>(c)];
        switch (joint.channels[c]) {
          case Channel::kXposition: translation.x() += value; break;
          case Channel::kYposition: translation.y() += value; break;
          case Channel::kZposition: translation.z() += value; break;
          default: rotation = rotation * AxisRotation(joint.channels[c], value);
        }
      }
      Eigen::Isometry3d local = Eigen::Isometry3d::Identity();
      local.translation() = translation;
      local.linear() = rotation;
      world[j] = joint.parent < 0 ? local : world[static_cast<size_t>(joint.parent)] * local;
      const Eigen::Quaterniond orientation(world[j].linear());
      double* pose = poses + j * 7;
      pose[0] = world[j].translation().x(), pose[1] = world[j].translation().y(), pose[2] = world[j].translation().z();
      pose[3] = orientation.w(), pose[4] = orientation.x(), pose[5] = orientation.y(), pose[6] = orientation.z();
    }
  };
  // The lead-in before a teleport (kTeleportSpeed) goes too: the take starts at the frame after the jump.
  const int64_t after_ease_in = first;
  const double rest_size = RestSize(joints);
  if (first > 0 && rest_size > 0) {
    std::vector<double> before(joints.size() * 7), after(joints.size() * 7);
    const int64_t last = std::min(frames_read - 2, after_ease_in + lead_frames);
    pose_joints(after_ease_in, before.data());
    for (int64_t k = after_ease_in + 1; k <= last; ++k) {
      pose_joints(k, after.data());
      double step = 0.0;
      for (size_t j = 0; j < joints.size(); ++j) {
        step = std::max(step, (Eigen::Map<const Eigen::Vector3d>(&after[j * 7]) - Eigen::Map<const Eigen::Vector3d>(&before[j * 7])).norm());
      }
      if (step / frame_time > kTeleportSpeed * rest_size) first = k;
      std::swap(before, after);
    }
  }
  const int64_t frames = frames_read - first;
  data.time_s.resize(static_cast<size_t>(frames));
  data.body_pose.resize(static_cast<size_t>(frames) * joints.size() * 7);
  for (int64_t t = 0; t < frames; ++t) {
    data.time_s[static_cast<size_t>(t)] = static_cast<double>(t) * frame_time;
    pose_joints(t + first, &data.body_pose[static_cast<size_t>(t) * joints.size() * 7]);
  }
  // The dropped frame 0 is the converters' calibration stance (CMU: a T-pose): kept beside the take.
  if (first > 0) {
    data.calibration_body_pose.resize(joints.size() * 7);
    pose_joints(0, data.calibration_body_pose.data());
  }

  // Facts for the user and for the scale rule.
  std::string layout;
  for (const BvhJoint& joint : joints) {
    if (joint.end_site) continue;
    std::string order;
    for (Channel channel : joint.channels) order += "XYZXYZ"[static_cast<int>(channel)];
    layout += (layout.empty() ? "" : " ") + joint.name + ":" + order;
  }
  const bool daz = joints[0].name == "hip";
  const bool cmu_hips = joints[0].name == "Hips";
  int joint_count = 0;
  bool mixed_arm_order = false;
  for (const BvhJoint& joint : joints) {
    if (joint.end_site) continue;
    ++joint_count;
    if (cmu_hips && joint.name.find("Elbow") != std::string::npos && joint.channels.size() == 3 &&
        joint.channels[1] == Channel::kXrotation) {
      mixed_arm_order = true;
    }
  }
  data.metadata["bvh"] = {{"joints", joint_count},
                          {"channels_per_frame", channel_count},
                          {"frames_in_file", frames_read},
                          {"frame_time_s", frame_time},
                          {"dropped_first_frame", first >= 1},
                          {"dropped_lead_frames", first},
                          {"dropped_ease_in_frames", after_ease_in - after_reference},
                          {"dropped_teleport_frames", first - after_ease_in},
                          {"dropped_held_frames", after_reference - before_hold},
                          {"rest_height_units", RestHeight(joints)},
                          {"channel_layout", layout},
                          {"convention", daz ? "cmu-daz" : (cmu_hips ? (mixed_arm_order ? "cmu-3dsmax" : "cmu-motionbuilder") : "unknown")}};
  if (frames_read < frames_wanted) data.warnings.push_back("fewer frames than the header declares");
  return data;
}

MarkerData ReadBvh(const std::string& path, const BvhOptions& options) {
  return ParseBvh(ReadFileText(path), path, options);
}

double GuessBvhScaleToMetres(MarkerData& data) {
  const double height = data.metadata.contains("bvh") ? data.metadata["bvh"].value("rest_height_units", 0.0) : 0.0;
  double scale = 1.0;
  if (height >= 10 && height < 50) scale = 0.056444;
  else if (height >= 50 && height < 100) scale = 0.0254;
  else if (height >= 100 && height < 250) scale = 0.01;
  else if (height >= 1 && height < 2.5) scale = 1.0;
  else data.warnings.push_back("cannot tell the BVH length unit from a rest height of " + std::to_string(height) +
                               " units; assuming metres (use --bvh-scale)");
  data.metadata["bvh"]["scale_to_m"] = scale;
  return scale;
}

}  // namespace syn
