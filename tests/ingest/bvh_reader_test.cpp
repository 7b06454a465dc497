#include "stages/ingest/bvh_reader.h"
#include "stages/ingest/ingest.h"
#include "stages/ingest/text_fields.h"

#include <gtest/gtest.h>

#include <Eigen/Geometry>
#include <cmath>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "common/error.h"
#include "common/file_bytes.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

const char* kTwoBones = R"(HIERARCHY
ROOT root
{
  OFFSET 0 0 0
  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation
  JOINT arm
  {
    OFFSET 10 0 0
    CHANNELS 3 Zrotation Xrotation Yrotation
    End Site
    {
      OFFSET 5 0 0
    }
  }
}
MOTION
Frames: 2
Frame Time: 0.5
1 2 3 0 0 0 0 0 0
0 0 0 90 0 0 0 90 0
)";

std::string With(const std::string& text, const std::string& from, const std::string& to);

Eigen::Vector3d Position(const MarkerData& data, int frame, int body) {
  const double* pose = &data.body_pose[(static_cast<size_t>(frame) * data.bodies.size() + static_cast<size_t>(body)) * 7];
  return {pose[0], pose[1], pose[2]};
}
Eigen::Quaterniond Orientation(const MarkerData& data, int frame, int body) {
  const double* pose = &data.body_pose[(static_cast<size_t>(frame) * data.bodies.size() + static_cast<size_t>(body)) * 7];
  return {pose[3], pose[4], pose[5], pose[6]};
}

TEST(BvhReader, KnownAnglesGiveKnownPoses) {
  const MarkerData data = ParseBvh(kTwoBones, "two.bvh", {});
  ASSERT_EQ(data.bodies, (std::vector<std::string>{"root", "arm", "arm_end"}));
  EXPECT_EQ(data.body_parents, (std::vector<std::string>{"", "root", "arm"}));
  EXPECT_DOUBLE_EQ(data.rate_hz, 2.0);
  ASSERT_EQ(data.frame_count(), 2);
  // Frame 0: the root moved to (1, 2, 3); nothing turned.
  EXPECT_LT((Position(data, 0, 1) - Eigen::Vector3d(11, 2, 3)).norm(), 1e-12);
  EXPECT_LT((Position(data, 0, 2) - Eigen::Vector3d(16, 2, 3)).norm(), 1e-12);
  // Frame 1: root turned 90° about Z: the arm's +X offset now points along +Y.
  EXPECT_LT((Position(data, 1, 1) - Eigen::Vector3d(0, 10, 0)).norm(), 1e-12);
  // The arm then turned 90° about its own X (after its Z, which is 0): the end site stays on the arm's X axis.
  EXPECT_LT((Position(data, 1, 2) - Eigen::Vector3d(0, 15, 0)).norm(), 1e-12);
  const Eigen::Quaterniond expected = Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitZ())) *
                                      Eigen::Quaterniond(Eigen::AngleAxisd(M_PI / 2, Eigen::Vector3d::UnitX()));
  EXPECT_LT(Orientation(data, 1, 1).angularDistance(expected), 1e-12);
  EXPECT_EQ(data.up_axis, 'y');
}

TEST(BvhReader, ChannelOrderMatters) {
  // The same two angles in two orders: Z then X, and X then Z, give different (known) orientations.
  std::string zx = R"(HIERARCHY
ROOT r
{
  OFFSET 0 0 0
  CHANNELS 3 Zrotation Xrotation Yrotation
  End Site
  {
    OFFSET 0 1 0
  }
}
MOTION
Frames: 1
Frame Time: 0.01
90 90 0
)";
  const std::string xz = With(zx, "Zrotation Xrotation", "Xrotation Zrotation");
  const MarkerData a = ParseBvh(zx, "zx.bvh", {});
  const MarkerData b = ParseBvh(xz, "xz.bvh", {});
  // R = Rz(90) Rx(90): (0,1,0) -> Rx -> (0,0,1) -> Rz -> (0,0,1).
  EXPECT_LT((Position(a, 0, 1) - Eigen::Vector3d(0, 0, 1)).norm(), 1e-12);
  // R = Rx(90) Rz(90): (0,1,0) -> Rz -> (-1,0,0) -> Rx -> (-1,0,0).
  EXPECT_LT((Position(b, 0, 1) - Eigen::Vector3d(-1, 0, 0)).norm(), 1e-12);
}

TEST(BvhReader, ImplausibleFrameCountIsAnError) {
  EXPECT_THROW((void)ParseBvh(With(kTwoBones, "Frames: 2", "Frames: 1e300"), "huge.bvh", {}), DataError);
}

TEST(BvhReader, DropFirstFrame) {
  BvhOptions options;
  options.drop_first_frame = true;
  const MarkerData data = ParseBvh(kTwoBones, "two.bvh", options);
  ASSERT_EQ(data.frame_count(), 1);
  EXPECT_LT((Position(data, 0, 1) - Eigen::Vector3d(0, 10, 0)).norm(), 1e-12);
  EXPECT_DOUBLE_EQ(data.time_s[0], 0.0);
  // The dropped frame is kept as the calibration stance: the same poses the kept first frame has.
  const MarkerData kept = ParseBvh(kTwoBones, "two.bvh", {});
  EXPECT_TRUE(kept.calibration_body_pose.empty());
  ASSERT_EQ(data.calibration_body_pose.size(), kept.bodies.size() * 7);
  for (size_t i = 0; i < data.calibration_body_pose.size(); ++i) {
    EXPECT_DOUBLE_EQ(data.calibration_body_pose[i], kept.body_pose[i]) << i;
  }
  EXPECT_DOUBLE_EQ(data.calibration_body_pose[7 + 0], 11.0);  // the arm at root (1,2,3) + offset (10,0,0)
}

// cgspeed's 07_12 has a second reference frame, every channel zero, after the first: dropped as well;
// a zero frame later in the take (or when the first frame is kept) is motion.
// kTwoBones with its reference frame followed by three frames, `rows` (one line each), instead of its one.
std::string ThreeFramesAfterTheReference(const std::string& rows) {
  return With(With(kTwoBones, "Frames: 2", "Frames: 4"), "0 0 0 90 0 0 0 90 0\n", rows);
}

TEST(BvhReader, DropFirstFrameAlsoDropsAllZeroReferenceFramesAfterIt) {
  const std::string three = ThreeFramesAfterTheReference("0 0 0 0 0 0 0 0 0\n0 0 0 90 0 0 0 90 0\n0 0 0 0 0 0 0 0 0\n");
  BvhOptions options;
  options.drop_first_frame = true;
  const MarkerData dropped = ParseBvh(three, "three.bvh", options);
  ASSERT_EQ(dropped.frame_count(), 2);
  EXPECT_LT((Position(dropped, 0, 1) - Eigen::Vector3d(0, 10, 0)).norm(), 1e-12);  // the 90° frame
  EXPECT_LT((Position(dropped, 1, 1) - Eigen::Vector3d(10, 0, 0)).norm(), 1e-12);  // the trailing zero frame stays
  EXPECT_EQ(ParseBvh(three, "three.bvh", {}).frame_count(), 4);
}

// Others leave one joint on the rest pose for a frame after the reference frame (cgspeed's CMU 05_01: the
// right ankle): that frame goes too. A joint that stays at zero through the take does not count.
TEST(BvhReader, DropFirstFrameAlsoDropsAFrameThatLeavesAJointAtRest) {
  // Frames: reference (all zero), the arm still at rest while the root has turned, then the take.
  const std::string partial = ThreeFramesAfterTheReference("0 0 0 30 0 0 0 0 0\n0 0 0 31 0 0 40 0 0\n0 0 0 32 0 0 41 0 0\n");
  BvhOptions options;
  options.drop_first_frame = true;
  const MarkerData dropped = ParseBvh(partial, "partial.bvh", options);
  ASSERT_EQ(dropped.frame_count(), 2);
  EXPECT_EQ(dropped.metadata.at("bvh").at("dropped_lead_frames"), 2);
  EXPECT_EQ(dropped.metadata.at("bvh").at("dropped_ease_in_frames"), 0);
  // The first kept frame is the one whose arm turned: the root 31° and the arm 40° about z, 71° from x.
  const Eigen::Vector3d arm = Position(dropped, 0, 2) - Position(dropped, 0, 1);
  EXPECT_NEAR(std::atan2(arm.y(), arm.x()) * 180 / M_PI, 71.0, 1e-9);
  // An arm at zero throughout is kept from frame 1.
  const std::string still = ThreeFramesAfterTheReference("0 0 0 30 0 0 0 0 0\n0 0 0 31 0 0 0 0 0\n0 0 0 32 0 0 0 0 0\n");
  EXPECT_EQ(ParseBvh(still, "still.bvh", options).frame_count(), 3);
}

// The real files: cgspeed's 05_01, 08_04 and 03_01 leave an ankle or a knee at rest in their frame 1.
TEST(BvhReader, RealCmuFramesLeavingAJointAtRestAreDropped) {
  SYN_REQUIRE_SHARED("cmu_bvh");
  BvhOptions options;
  options.drop_first_frame = true;
  for (const char* file : {"05/05_01.bvh", "08/08_04.bvh", "03/03_01.bvh"}) {
    const MarkerData data = ReadBvh(testing::SharedPath(std::string("cmu_bvh/") + file), options);
    EXPECT_EQ(data.metadata.at("bvh").at("dropped_lead_frames"), 2) << file;
    // The take now starts moving as it goes on: no body turns more between its first two frames than
    // twice its largest turn between the next two (05_01's right foot turned 22° against 5° before).
    double first_step = 0.0, next_step = 0.0;
    for (int b = 0; b < static_cast<int>(data.bodies.size()); ++b) {
      first_step = std::max(first_step, Orientation(data, 0, b).angularDistance(Orientation(data, 1, b)));
      next_step = std::max(next_step, Orientation(data, 1, b).angularDistance(Orientation(data, 2, b)));
    }
    EXPECT_LT(first_step, 2 * next_step) << file << ": " << first_step * 180 / M_PI << " deg then " << next_step * 180 / M_PI;
  }
}

// kTwoBones at 120 Hz with `arm_z` as the arm's Z rotation, frame by frame.
std::string ArmTake(const std::vector<double>& arm_z) {
  std::string text = std::string(kTwoBones).substr(0, std::string(kTwoBones).find("Frames:"));
  text += "Frames: " + std::to_string(arm_z.size()) + "\nFrame Time: 0.00833333\n";
  for (const double z : arm_z) text += "0 0 0 0 0 0 " + std::to_string(z) + " 0 0\n";
  return text;
}

// An ArmTake's arm angle (degrees, about Z) in frame `frame`, from the arm joint to its end site.
double ArmAngleDeg(const MarkerData& data, int frame) {
  const Eigen::Vector3d arm = Position(data, frame, 2) - Position(data, frame, 1);
  return std::atan2(arm.y(), arm.x()) * 180 / M_PI;
}

// `lead` (arm angles, deg, frame 0 first), then the take proper: 20 frames from `from`, 0.1° a frame.
std::vector<double> ThenSlowly(std::vector<double> lead, double from) {
  for (int k = 0; k < 20; ++k) lead.push_back(from + 0.1 * k);
  return lead;
}

// Some conversions ease in from the rest frame over a few frames (CMU's lawrennd, Przestr and papagina
// copies): those frames go with it. The arm sweeps 0 -> 59.5° in five frames (220-735 °/s RMS over the six
// rotation channels), then moves 0.1° a frame: the take starts at 59.5°.
TEST(BvhReader, DropFirstFrameAlsoDropsTheEaseInFromIt) {
  const std::vector<double> arm = ThenSlowly({0, 15, 30, 45, 55, 59.5}, 60);
  BvhOptions options;
  options.drop_first_frame = true;
  const MarkerData eased = ParseBvh(ArmTake(arm), "eased.bvh", options);
  ASSERT_EQ(eased.frame_count(), 21);
  EXPECT_NEAR(ArmAngleDeg(eased, 0), 59.5, 1e-9);
  EXPECT_EQ(eased.metadata.at("bvh").at("dropped_ease_in_frames"), 4);
  // The calibration stance is still the rest frame.
  ASSERT_EQ(eased.calibration_body_pose.size(), eased.bodies.size() * 7);
  EXPECT_NEAR(eased.calibration_body_pose[2 * 7 + 1], 0.0, 1e-12);  // the arm's end straight along x
  // A take that starts at once keeps its frame 1 (cgspeed's T-pose, then the take), and so does one whose
  // fast start is a single step.
  const std::vector<double> at_once = ThenSlowly({0, 60}, 60);
  EXPECT_EQ(ParseBvh(ArmTake(at_once), "at_once.bvh", options).frame_count(), 21);
  const std::vector<double> one_fast_step = ThenSlowly({0, 40, 60}, 60);
  EXPECT_EQ(ParseBvh(ArmTake(one_fast_step), "one_step.bvh", options).frame_count(), 22);
  // Without drop_first_frame nothing is dropped.
  EXPECT_EQ(ParseBvh(ArmTake(arm), "eased.bvh", {}).frame_count(), 26);
}

// A lead-in that ends in a teleport (bvh_reader.cpp kTeleportSpeed) goes with the calibration frame: the arm
// holds near 1° for frames 1-5 (not at rest: frames left at zero go by another rule), then turns to 170° in
// one frame (its end 10 units in 1/120 s, 80 rest-pose sizes per second; a body moves at most about 9), then
// moves 0.1° a frame. The same jump after the first 0.5 s is
// kept (the take's own glitch, not its lead-in), and so is a fast but possible step (20° in a frame, 14 sizes/s).
TEST(BvhReader, DropFirstFrameAlsoDropsALeadInEndedByATeleport) {
  const std::vector<double> lead_in = ThenSlowly({0, 1, 1.01, 1.02, 1.03, 1.04}, 170);
  BvhOptions options;
  options.drop_first_frame = true;
  const MarkerData jumped = ParseBvh(ArmTake(lead_in), "lead_in.bvh", options);
  ASSERT_EQ(jumped.frame_count(), 20);
  EXPECT_EQ(jumped.metadata.at("bvh").at("dropped_teleport_frames"), 5);
  EXPECT_EQ(jumped.metadata.at("bvh").at("dropped_lead_frames"), 6);
  EXPECT_NEAR(ArmAngleDeg(jumped, 0), 170, 1e-9);
  std::vector<double> late = {0};  // the jump at frame 66, 0.54 s after frame 1
  for (int k = 1; k < 66; ++k) late.push_back(1 + 0.01 * k);
  const MarkerData kept = ParseBvh(ArmTake(ThenSlowly(late, 170)), "late.bvh", options);
  EXPECT_EQ(kept.frame_count(), 85);
  EXPECT_EQ(kept.metadata.at("bvh").at("dropped_teleport_frames"), 0);
  const std::vector<double> fast = ThenSlowly({0, 1, 1.01, 21}, 21);
  EXPECT_EQ(ParseBvh(ArmTake(fast), "fast.bvh", options).frame_count(), 23);
}

// A take that holds its first pose, every channel repeated exactly, before it moves (CMU 08_07: 6 frames,
// then its hips jump 9 cm in a frame): the hold goes, its last frame with it. A single repeated pair is kept
// (a file that rounds its channels can repeat one by chance), and so is a take that holds still longer than
// 0.5 s (a static trial).
TEST(BvhReader, DropFirstFrameAlsoDropsAHeldLeadIn) {
  BvhOptions options;
  options.drop_first_frame = true;
  const std::vector<double> held = ThenSlowly({0, 30, 30, 30, 30, 30}, 35);
  const MarkerData moved = ParseBvh(ArmTake(held), "held.bvh", options);
  EXPECT_EQ(moved.frame_count(), 20);
  EXPECT_EQ(moved.metadata.at("bvh").at("dropped_held_frames"), 5);
  EXPECT_NEAR(ArmAngleDeg(moved, 0), 35, 1e-9);
  const std::vector<double> pair = ThenSlowly({0, 30, 30}, 30.5);
  EXPECT_EQ(ParseBvh(ArmTake(pair), "pair.bvh", options).frame_count(), 22);
  const std::vector<double> still(80, 30.0);  // 0.66 s of one pose after frame 0
  std::vector<double> static_take = {0};
  static_take.insert(static_take.end(), still.begin(), still.end());
  const MarkerData kept = ParseBvh(ArmTake(static_take), "still.bvh", options);
  EXPECT_EQ(kept.frame_count(), 80);
  EXPECT_EQ(kept.metadata.at("bvh").at("dropped_held_frames"), 0);
}

// CMU 03_02 holds its T-pose arms for 50 frames while its legs walk, then its hands jump 69 cm in a frame:
// those frames are dropped. The ingest summary says so.
TEST(BvhReader, RealCmuLeadInBeforeATeleportIsDropped) {
  SYN_REQUIRE_SHARED("cmu_bvh/03/03_02.bvh");
  IngestOptions options;
  options.drop_first_frame = true;
  IngestSummary summary;
  const MarkerData take = IngestCapture(testing::SharedPath("cmu_bvh/03/03_02.bvh"), options, &summary);
  EXPECT_EQ(summary.dropped_teleport_frames, 50);
  EXPECT_EQ(summary.dropped_held_frames, 0);
  EXPECT_EQ(summary.dropped_lead_frames, 51);
  EXPECT_NE(summary.BriefReport().find("50 before a joint jumped faster than any body moves"), std::string::npos)
      << summary.BriefReport();
  // What is left moves like a body: no joint faster than 10 statures (here the rest pose's height) a second.
  const auto hands = std::find(take.bodies.begin(), take.bodies.end(), "RightHand") - take.bodies.begin();
  double fastest = 0;
  for (int64_t t = 1; t < take.frame_count(); ++t) {
    const double* before = &take.body_pose[(static_cast<size_t>(t - 1) * take.bodies.size() + static_cast<size_t>(hands)) * 7];
    const double* after = &take.body_pose[(static_cast<size_t>(t) * take.bodies.size() + static_cast<size_t>(hands)) * 7];
    fastest = std::max(fastest, std::hypot(after[0] - before[0], after[1] - before[1], after[2] - before[2]) /
                                    (take.time_s[1] - take.time_s[0]));
  }
  EXPECT_LT(fastest, 10.0) << "m/s, the right hand";
}

// The real files: a lawrennd-family copy eases in over frames 1-4, cgspeed's starts at frame 1.
TEST(BvhReader, RealCmuEaseInsAreDroppedAndCgspeedTakesKept) {
  SYN_REQUIRE_SHARED("cmu_bvh");
  BvhOptions options;
  options.drop_first_frame = true;
  const MarkerData eased = ReadBvh(testing::SharedPath("cmu_bvh/12/12_02.bvh"), options);
  EXPECT_EQ(eased.metadata.at("bvh").at("dropped_ease_in_frames"), 3);
  EXPECT_EQ(eased.frame_count(), 674 - 4);
  const MarkerData cgspeed = ReadBvh(testing::SharedPath("cmu_bvh/02/02_01.bvh"), options);
  EXPECT_EQ(cgspeed.metadata.at("bvh").at("dropped_ease_in_frames"), 0);
  EXPECT_EQ(cgspeed.frame_count(), 343);
  EXPECT_EQ(eased.metadata.at("bvh").at("dropped_teleport_frames"), 0);
  EXPECT_EQ(cgspeed.metadata.at("bvh").at("dropped_teleport_frames"), 0);
  EXPECT_EQ(eased.metadata.at("bvh").at("dropped_held_frames"), 0);
  EXPECT_EQ(cgspeed.metadata.at("bvh").at("dropped_held_frames"), 0);
  IngestOptions ingest;
  ingest.drop_first_frame = true;
  IngestSummary held;
  (void)IngestCapture(testing::SharedPath("cmu_bvh/08/08_07.bvh"), ingest, &held);
  EXPECT_EQ(held.dropped_held_frames, 6);
  EXPECT_EQ(held.dropped_lead_frames, 7);
  EXPECT_NE(held.BriefReport().find("6 holding one pose before the take moves"), std::string::npos) << held.BriefReport();
}

// syn-ingest's summary line says what the start lost.
TEST(BvhReader, TheIngestSummarySaysWhichLeadFramesWereDropped) {
  SYN_REQUIRE_SHARED("cmu_bvh");
  IngestOptions options;
  options.drop_first_frame = true;
  IngestSummary eased, cgspeed, kept;
  (void)IngestCapture(testing::SharedPath("cmu_bvh/12/12_02.bvh"), options, &eased);
  (void)IngestCapture(testing::SharedPath("cmu_bvh/02/02_01.bvh"), options, &cgspeed);
  (void)IngestCapture(testing::SharedPath("cmu_bvh/02/02_01.bvh"), {}, &kept);
  EXPECT_EQ(eased.dropped_lead_frames, 4);
  EXPECT_EQ(eased.dropped_ease_in_frames, 3);
  EXPECT_NE(eased.BriefReport().find("the first 4 frames dropped (the calibration frame, kept aside; 3 easing in from it)"),
            std::string::npos) << eased.BriefReport();
  EXPECT_NE(cgspeed.BriefReport().find("frame 0 dropped (the calibration frame, kept aside)"), std::string::npos)
      << cgspeed.BriefReport();
  EXPECT_EQ(kept.dropped_lead_frames, 0);
  EXPECT_EQ(kept.BriefReport().find("dropped"), std::string::npos) << kept.BriefReport();
}

// text with the first `from` replaced by `to` (built by concatenation: GCC 12 warns falsely on
// std::string::replace at -O2).
std::string With(const std::string& text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  return text.substr(0, at) + to + text.substr(at + from.size());
}

int64_t ErrorLine(const std::string& text) {
  try {
    (void)ParseBvh(text, "bad.bvh", {});
  } catch (const DataError& error) {
    return error.where().line;
  }
  return -1;
}

TEST(BvhReader, MalformedInputIsLocated) {
  const std::string text = kTwoBones;
  // Unknown channel (line 5).
  EXPECT_EQ(ErrorLine(With(text, "Zrotation Xrotation Yrotation\n  JOINT", "Wrotation Xrotation Yrotation\n  JOINT")), 5);
  // Too few values on the second frame line (20).
  EXPECT_EQ(ErrorLine(With(text, "0 0 0 90 0 0 0 90 0", "0 0 0 90 0 0 0 90")), 20);
  // A non-numeric value on the first frame line (19).
  EXPECT_EQ(ErrorLine(With(text, "1 2 3", "x 2 3")), 19);
  // Missing closing brace: MOTION (now line 15) comes where JOINT, End or } is expected.
  EXPECT_EQ(ErrorLine(With(text, "}\nMOTION", "MOTION")), 15);
  // Fewer frames than declared.
  EXPECT_GT(ErrorLine(With(text, "Frames: 2", "Frames: 3")), 0);
  // A frame count the file cannot hold is refused before allocating.
  EXPECT_GT(ErrorLine(With(text, "Frames: 2", "Frames: 999999999999")), 0);
}

// The format's grammar, held to so that reading costs what the file holds: a joint without CHANNELS (the
// fuzzer's find: a hierarchy of none, a blank frame line, a read past an empty frame buffer) or a second End
// Site on one joint (a second body of the same name) is refused at its line.
TEST(BvhReader, JointsNeedChannelsAndAtMostOneEndSite) {
  const std::string text = kTwoBones;
  // The root without its CHANNELS line (line 5): JOINT comes where CHANNELS is expected.
  EXPECT_EQ(ErrorLine(With(text, "  CHANNELS 6 Xposition Yposition Zposition Zrotation Xrotation Yrotation\n", "")), 5);
  // No channel anywhere, frames of blank lines.
  EXPECT_EQ(ErrorLine("HIERARCHY\nROOT a\n{\nOFFSET 0 0 0\n}\nMOTION\nFrames: 1\nFrame Time: 0.01\n\n\n"), 5);
  EXPECT_EQ(ErrorLine(With(text, "CHANNELS 3 Zrotation Xrotation Yrotation", "CHANNELS 0")), 9);
  // Two End Sites on the arm: the second's "Site" (line 14).
  EXPECT_EQ(ErrorLine(With(text, "      OFFSET 5 0 0\n    }\n", "      OFFSET 5 0 0\n    }\n    End Site\n    {\n      OFFSET 5 0 0\n    }\n")),
            14);
}

// Same numbers, NaN equal to NaN (missing stays missing).
bool SameValues(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    if (!(a[i] == b[i] || (std::isnan(a[i]) && std::isnan(b[i])))) return false;
  }
  return true;
}

// Every prefix of a small BVH, and a damaged copy, either reads as the whole file does (the cut fell in
// trailing whitespace) or is refused with a DataError at a line of that file; never a crash, never a
// half-read motion taken as whole.
TEST(BvhReader, TruncatedAndGarbageInputsReadRightOrAreRefusedAtALine) {
  const std::string text = kTwoBones;
  const MarkerData full = ParseBvh(text, "full.bvh", {});
  int read = 0, refused = 0;
  const auto check = [&](const std::string& input, const std::string& name, size_t cut) {
    try {
      const MarkerData data = ParseBvh(input, name, {});
      ++read;
      EXPECT_EQ(data.frame_count(), full.frame_count()) << name << " cut at " << cut;
      EXPECT_EQ(data.bodies, full.bodies) << name << " cut at " << cut;
      EXPECT_TRUE(SameValues(data.body_pose, full.body_pose)) << name << " cut at " << cut;
      EXPECT_TRUE(SameValues(data.points, full.points)) << name << " cut at " << cut;
    } catch (const DataError& error) {
      ++refused;
      EXPECT_EQ(error.where().file, name) << error.what();
      EXPECT_GT(error.where().line, 0) << name << " cut at " << cut << ": " << error.what();
      EXPECT_NE(std::string(error.what()).find(name + ":"), std::string::npos) << error.what();
    }
  };
  for (size_t cut = 0; cut < text.size(); ++cut) check(text.substr(0, cut), "cut.bvh", cut);
  EXPECT_GE(read, 1) << "the cut of the final newline reads as the whole file";
  EXPECT_GT(refused, static_cast<int>(text.size()) - 5);
  std::string garbage = text;
  for (size_t i = 0; i < garbage.size(); i += 7) garbage[i] = static_cast<char>((i * 131) % 256);
  read = 0;
  try {
    (void)ParseBvh(garbage, "garbage.bvh", {});
    ADD_FAILURE() << "a BVH with every 7th byte replaced was accepted";
  } catch (const DataError& error) {
    EXPECT_EQ(error.where().file, "garbage.bvh");
    EXPECT_GT(error.where().line, 0) << error.what();
  }
}

struct IndexRow {
  std::string trial, file;
  int64_t frames = 0;
  double rate = 0;
  int joints = 0;
};

std::vector<IndexRow> ReadIndex() {
  std::ifstream in(testing::SharedPath("cmu_bvh/index.csv"));
  std::vector<IndexRow> rows;
  std::string line;
  std::getline(in, line);
  while (std::getline(in, line)) {
    const std::vector<std::string> cells = SplitQuotedCsv(line);
    IndexRow row;
    row.trial = cells[1];
    row.file = cells[2];
    row.frames = std::stoll(cells[6]);
    row.rate = std::stod(cells[7]);
    row.joints = std::stoi(cells[8]);
    rows.push_back(row);
  }
  return rows;
}

TEST(BvhReader, AllCmuTrialsAgreeWithTheIndex) {
  SYN_REQUIRE_SHARED("cmu_bvh/index.csv");
  const std::vector<IndexRow> rows = ReadIndex();
  ASSERT_EQ(rows.size(), 51u);
  for (const IndexRow& row : rows) {
    SCOPED_TRACE(row.file);
    MarkerData data = ReadBvh(testing::SharedPath("cmu_bvh/" + row.file), {});
    EXPECT_EQ(data.frame_count(), row.frames);
    EXPECT_NEAR(data.rate_hz, row.rate, 5e-4);
    EXPECT_EQ(data.metadata["bvh"]["joints"].get<int>(), row.joints);
    // Bone lengths stay equal to |OFFSET| in every frame: FK composes rigid transforms.
    const size_t bodies = data.bodies.size();
    for (size_t b = 1; b < bodies; ++b) {
      const auto parent = std::find(data.bodies.begin(), data.bodies.end(), data.body_parents[b]) - data.bodies.begin();
      const double first = (Position(data, 0, static_cast<int>(b)) - Position(data, 0, static_cast<int>(parent))).norm();
      const int last = static_cast<int>(data.frame_count()) - 1;
      const double later = (Position(data, last, static_cast<int>(b)) - Position(data, last, static_cast<int>(parent))).norm();
      ASSERT_NEAR(first, later, 1e-9 * (1 + first)) << data.bodies[b];
    }
    // The CMU unit rule gives a human standing height.
    const double height = data.metadata["bvh"]["rest_height_units"].get<double>() * GuessBvhScaleToMetres(data);
    EXPECT_GT(height, 1.2);
    EXPECT_LT(height, 2.0);
  }
}

TEST(BvhReader, RootFollowsItsChannels) {
  SYN_REQUIRE_SHARED("cmu_bvh/02/02_01.bvh");
  const std::string text = ReadFileText(testing::SharedPath("cmu_bvh/02/02_01.bvh"));
  const MarkerData data = ParseBvh(text, "02_01.bvh", {});
  // Independent: the first numbers of the 11th frame line are the root position (its OFFSET is 0 0 0).
  std::istringstream in(text.substr(text.find("Frame Time:")));
  std::string line;
  std::getline(in, line);
  for (int i = 0; i <= 10; ++i) std::getline(in, line);
  std::istringstream values(line);
  Eigen::Vector3d root;
  values >> root.x() >> root.y() >> root.z();
  EXPECT_LT((Position(data, 10, 0) - root).norm(), 1e-9);
}

}  // namespace
}  // namespace syn
