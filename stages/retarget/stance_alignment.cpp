#include "stages/retarget/stance_alignment.h"

#include <algorithm>
#include <array>
#include <cmath>

#include <Eigen/Geometry>

#include "common/percentile.h"

namespace syn {
namespace {

constexpr const char* kSides[2] = {"left", "right"};

int64_t LandmarkIndex(const LandmarkTrajectories& landmarks, const std::string& name) {
  const auto found = std::find(landmarks.names.begin(), landmarks.names.end(), name);
  return found == landmarks.names.end() ? -1 : found - landmarks.names.begin();
}

// A named landmark's position in a frame; false when the marker set has no such landmark or it is missing.
bool LandmarkPosition(const LandmarkTrajectories& landmarks, const std::string& name, int64_t frame,
                      Eigen::Vector3d* position) {
  const int64_t index = LandmarkIndex(landmarks, name);
  if (index < 0) return false;
  const LandmarkSample sample = SampleAt(landmarks, frame, index);
  *position = sample.position;
  return sample.valid;
}

// The robot link pose of the task tracking `landmark` in the reference stance; false when none does.
bool RobotLandmarkPosition(const RobotStance& robot, const std::string& landmark, Eigen::Vector3d* position) {
  const auto found = std::find(robot.task_landmarks.begin(), robot.task_landmarks.end(), landmark);
  if (found == robot.task_landmarks.end()) return false;
  *position = robot.link_reference[static_cast<size_t>(found - robot.task_landmarks.begin())].translation();
  return true;
}

// Robot / subject height of `landmark` above the mean of the feet at the reference; NaN when either cannot
// be measured.
double HeightRatioAboveFeet(const LandmarkTrajectories& landmarks, const RobotStance& robot, const std::string& landmark,
                            int64_t reference) {
  Eigen::Vector3d top, left, right, robot_top, robot_left, robot_right;
  if (!LandmarkPosition(landmarks, landmark, reference, &top) || !LandmarkPosition(landmarks, "left_foot", reference, &left) ||
      !LandmarkPosition(landmarks, "right_foot", reference, &right) || !RobotLandmarkPosition(robot, landmark, &robot_top) ||
      !RobotLandmarkPosition(robot, "left_foot", &robot_left) || !RobotLandmarkPosition(robot, "right_foot", &robot_right)) {
    return std::nan("");
  }
  const double subject = top.z() - 0.5 * (left.z() + right.z());
  const double robot_height = robot_top.z() - 0.5 * (robot_left.z() + robot_right.z());
  // A subject "height" under 0.3 m is a crouch or a broken capture, not a proportion.
  return subject > 0.3 && robot_height > 0 ? robot_height / subject : std::nan("");
}

// Robot / subject arm length, the mean over the sides both have; NaN when neither side can be measured.
double ArmRatio(const LandmarkTrajectories& landmarks, const RobotStance& robot, int64_t reference) {
  double sum = 0;
  int sides = 0;
  for (int side = 0; side < 2; ++side) {
    Eigen::Vector3d elbow, hand;
    const std::string prefix = kSides[side];
    if (!std::isfinite(robot.arm_length[side]) || !LandmarkPosition(landmarks, prefix + "_elbow", reference, &elbow) ||
        !LandmarkPosition(landmarks, prefix + "_hand", reference, &hand)) {
      continue;
    }
    Eigen::Vector3d shoulder;
    if (!LandmarkPosition(landmarks, prefix + "_shoulder", reference, &shoulder)) continue;
    const double subject = (elbow - shoulder).norm() + (hand - elbow).norm();
    if (subject < 0.1) continue;  // landmarks on one point: a marker set that cannot tell them apart
    sum += robot.arm_length[side] / subject, ++sides;
  }
  return sides ? sum / sides : std::nan("");
}

// Robot / subject leg length, the mean over the sides both have; NaN when neither side can be measured.
double LegRatio(const LandmarkTrajectories& landmarks, const RobotStance& robot, int64_t reference) {
  double sum = 0;
  int sides = 0;
  for (int side = 0; side < 2; ++side) {
    Eigen::Vector3d hip, knee, ankle;
    const std::string prefix = kSides[side];
    if (!std::isfinite(robot.leg_length[side]) || !LandmarkPosition(landmarks, prefix + "_hip", reference, &hip) ||
        !LandmarkPosition(landmarks, prefix + "_knee", reference, &knee) ||
        !LandmarkPosition(landmarks, prefix + "_foot", reference, &ankle)) {
      continue;
    }
    // Segment by segment: a bent knee at the reference frame does not shorten it.
    const double subject = (knee - hip).norm() + (ankle - knee).norm();
    if (subject < 0.3) continue;  // as HeightRatioAboveFeet: not a leg
    sum += robot.leg_length[side] / subject, ++sides;
  }
  return sides ? sum / sides : std::nan("");
}

// Rotation about Z that turns the subject's forward direction (left × up) into +X.
Eigen::Matrix3d HeadingAlignment(const Eigen::Vector3d& left, double* heading) {
  Eigen::Vector3d forward = left.cross(Eigen::Vector3d::UnitZ());
  forward.z() = 0;
  if (forward.norm() < 1e-9) {
    *heading = 0;
    return Eigen::Matrix3d::Identity();
  }
  *heading = std::atan2(forward.y(), forward.x());
  return Eigen::AngleAxisd(-*heading, Eigen::Vector3d::UnitZ()).toRotationMatrix();
}

// The landmark pairs whose left-minus-right vectors give the body's left: feet and elbows, as indices
// (-1: the marker set has no such landmark), found once rather than by name in every frame.
struct LeftRightPairs {
  int64_t pairs[2][2];
  explicit LeftRightPairs(const LandmarkTrajectories& landmarks)
      : pairs{{LandmarkIndex(landmarks, "left_foot"), LandmarkIndex(landmarks, "right_foot")},
              {LandmarkIndex(landmarks, "left_elbow"), LandmarkIndex(landmarks, "right_elbow")}} {}
};

// The body's right-to-left direction in a frame, from the feet and the elbows (zero when neither pair is there).
Eigen::Vector3d BodyLeft(const LandmarkTrajectories& landmarks, const LeftRightPairs& sides, int64_t frame) {
  Eigen::Vector3d left = Eigen::Vector3d::Zero();
  for (const auto& pair : sides.pairs) {
    if (pair[0] < 0 || pair[1] < 0) continue;
    const LandmarkSample a = SampleAt(landmarks, frame, pair[0]), b = SampleAt(landmarks, frame, pair[1]);
    if (a.valid && b.valid) left += a.position - b.position;
  }
  return left;
}

// The subject's left at the reference frame (with heading_from_pelvis). A frame chosen for its landmarks (no
// --reference-time) is usually mid-motion: mid-stride the feet's left-right vector is turned by the stride,
// up to 45° on a CMU walk, and the robot then walked crabwise (02_01: 40° between where it faced and where it
// went). With a pelvis orientation, the left is instead the pelvis frame's axis nearest to the feet's and
// elbows' left-right vectors averaged over the whole capture in the pelvis frame, taken at the reference
// frame; the axis is snapped (marker-set and BVH pelvis frames have one pointing left) so an asymmetric
// motion (a lunge, a turn) cannot bias it.
Eigen::Vector3d SubjectLeft(const LandmarkTrajectories& landmarks, int64_t reference, bool heading_from_pelvis) {
  const LeftRightPairs sides(landmarks);
  const Eigen::Vector3d at_reference = BodyLeft(landmarks, sides, reference);
  const int64_t pelvis = LandmarkIndex(landmarks, "pelvis");
  if (!heading_from_pelvis || pelvis < 0) return at_reference;
  const LandmarkSample pelvis_at_reference = SampleAt(landmarks, reference, pelvis);
  if (!pelvis_at_reference.valid || !pelvis_at_reference.has_orientation) return at_reference;
  Eigen::Vector3d mean_left = Eigen::Vector3d::Zero();
  for (int64_t t = 0; t < landmarks.frames; ++t) {
    const LandmarkSample pelvis_sample = SampleAt(landmarks, t, pelvis);
    const Eigen::Vector3d left = BodyLeft(landmarks, sides, t);
    if (!pelvis_sample.valid || !pelvis_sample.has_orientation || left.norm() < 1e-6) continue;
    mean_left += pelvis_sample.orientation.conjugate() * left.normalized();
  }
  if (mean_left.norm() < 1e-6) return at_reference;
  Eigen::Index axis = 0;
  mean_left.cwiseAbs().maxCoeff(&axis);
  Eigen::Vector3d pelvis_left = Eigen::Vector3d::Zero();
  pelvis_left[axis] = mean_left[axis] > 0 ? 1.0 : -1.0;
  return pelvis_at_reference.orientation * pelvis_left;
}

// Links from `link` up to the root, `link` first.
std::vector<std::string> LinksToRoot(const Model& model, std::string link) {
  std::vector<std::string> path{link};
  const auto& joints = model.joints();
  for (size_t guard = 0; guard <= joints.size(); ++guard) {
    const auto joint = std::find_if(joints.begin(), joints.end(), [&](const ModelJoint& j) { return j.child == link; });
    if (joint == joints.end()) break;
    link = joint->parent;
    path.push_back(link);
  }
  return path;
}

// The two chains' paths from `ends` up to the root, and per chain the index in its path of the link just
// below the first link the other chain shares (the body both hang from); 0 where they do not part.
struct Branches {
  std::vector<std::string> paths[2];
  size_t below_branch[2] = {0, 0};
  Branches(const Model& model, const std::string (&ends)[2]) {
    for (int side = 0; side < 2; ++side) paths[side] = LinksToRoot(model, ends[side]);
    for (int side = 0; side < 2; ++side) {
      const std::vector<std::string>& path = paths[side];
      const std::vector<std::string>& other = paths[1 - side];
      size_t branch = 0;
      while (branch < path.size() && std::find(other.begin(), other.end(), path[branch]) == other.end()) ++branch;
      below_branch[side] = branch == 0 || branch == path.size() ? 0 : branch - 1;
    }
  }
};

// The robot link the map's task on `landmark` drives ("" when no task names it).
std::string TaskLinkOf(const RobotStance& stance, const std::vector<std::string>& task_links, const std::string& landmark) {
  const std::vector<std::string>& task_landmarks = stance.task_landmarks;
  const auto found = std::find(task_landmarks.begin(), task_landmarks.end(), landmark);
  return found == task_landmarks.end() ? std::string() : task_links[static_cast<size_t>(found - task_landmarks.begin())];
}

Eigen::Vector3d LinkPosition(const Model& model, Workspace& workspace, const std::string& link) {
  return workspace.findLinkPose(model.findLinkIndex(link)).translation();
}

// How much higher an arm may be raised at the reference frame than it is over most of the take before its
// reference moves to a frame where it is as it mostly is (NeutralReference). A T-pose's arms are 75-80°
// above a walker's; the first frames of the other shared CMU walks and dances are at most 24° above their
// take's median (07_01's left arm).
constexpr double kRaisedArmMargin = 45.0 * M_PI / 180.0;

// The arm's elevation at frame t: the angle of its hand from straight down, seen from `shoulder`; NaN where
// either is missing.
double ArmElevation(const LandmarkTrajectories& landmarks, int64_t hand, int64_t shoulder, int64_t t) {
  const LandmarkSample at_hand = SampleAt(landmarks, t, hand), at_shoulder = SampleAt(landmarks, t, shoulder);
  if (!at_hand.valid || !at_shoulder.valid) return std::nan("");
  const Eigen::Vector3d arm = at_hand.position - at_shoulder.position;
  const double length = arm.norm();
  return length > 0.0 ? std::acos(std::clamp(-arm.z() / length, -1.0, 1.0)) : std::nan("");
}

// The frame one arm's reference is taken from: `reference`, unless the arm is raised there more than
// kRaisedArmMargin above its median elevation over the take (nearest rank, over the frames `usable` marks);
// then the first of those frames at or below that median.
int64_t TypicalArmFrame(const LandmarkTrajectories& landmarks, int64_t reference, int64_t hand, int64_t shoulder,
                        const std::vector<bool>& usable) {
  const double at_reference = ArmElevation(landmarks, hand, shoulder, reference);
  if (!std::isfinite(at_reference)) return reference;
  std::vector<double> elevations(static_cast<size_t>(landmarks.frames), std::nan(""));
  std::vector<double> finite;
  for (int64_t t = 0; t < landmarks.frames; ++t) {
    if (!usable[static_cast<size_t>(t)]) continue;
    const double elevation = elevations[static_cast<size_t>(t)] = ArmElevation(landmarks, hand, shoulder, t);
    if (std::isfinite(elevation)) finite.push_back(elevation);
  }
  if (finite.empty()) return reference;
  const double median = NearestRankPercentile(finite, 0.5);
  if (at_reference - median <= kRaisedArmMargin) return reference;
  for (int64_t t = 0; t < landmarks.frames; ++t) {
    if (elevations[static_cast<size_t>(t)] <= median) return t;
  }
  return reference;
}

}  // namespace

void MeasureRobotLegs(const Model& model, Workspace& workspace, const std::vector<std::string>& task_links,
                      RobotStance& stance) {
  const auto link_of = [&](const std::string& landmark) { return TaskLinkOf(stance, task_links, landmark); };
  const std::string feet[2] = {link_of("left_foot"), link_of("right_foot")};
  if (feet[0].empty() || feet[1].empty()) return;
  const Branches legs(model, feet);
  const auto position = [&](const std::string& link) { return LinkPosition(model, workspace, link); };
  for (int side = 0; side < 2; ++side) {
    const size_t hip = legs.below_branch[side];
    if (hip == 0) continue;  // the foot link is itself where the chains part: no leg
    stance.leg_length[side] = (position(legs.paths[side][hip]) - position(feet[side])).norm();
  }
}

void MeasureRobotArms(const Model& model, Workspace& workspace, const std::vector<std::string>& task_links,
                      RobotStance& stance) {
  const auto link_of = [&](const std::string& landmark) { return TaskLinkOf(stance, task_links, landmark); };
  const std::string hands[2] = {link_of("left_hand"), link_of("right_hand")};
  if (hands[0].empty() || hands[1].empty()) return;
  const Branches arms(model, hands);
  const auto position = [&](const std::string& link) { return LinkPosition(model, workspace, link); };
  for (int side = 0; side < 2; ++side) {
    const std::vector<std::string>& path = arms.paths[side];
    const std::string elbow = link_of(std::string(kSides[side]) + "_elbow");
    const size_t below_branch = arms.below_branch[side];
    if (below_branch == 0) continue;
    const auto elbow_at = std::find(path.begin(), path.begin() + static_cast<std::ptrdiff_t>(below_branch + 1), elbow);
    if (elbow.empty() || elbow_at == path.begin() + static_cast<std::ptrdiff_t>(below_branch + 1)) continue;
    // The link just below the branch: its frame origin is the shoulder's first joint.
    const Eigen::Vector3d shoulder = position(path[below_branch]);
    stance.arm_length[side] = (position(elbow) - shoulder).norm() + (position(hands[side]) - position(elbow)).norm();
  }
}

StanceAlignment AlignToRobot(const LandmarkTrajectories& landmarks, const RobotStance& robot, int64_t reference,
                             const AlignmentOptions& options, std::vector<std::string>& notes) {
  StanceAlignment alignment;
  alignment.heading = HeadingAlignment(SubjectLeft(landmarks, reference, options.heading_from_pelvis), &alignment.heading_rad);
  alignment.on_arm.assign(static_cast<size_t>(landmarks.count()), false);
  if (options.fixed_scale > 0) {
    alignment.leg_scale = alignment.arm_scale = options.fixed_scale;
    return alignment;
  }
  double legs = options.per_chain ? LegRatio(landmarks, robot, reference) : std::nan("");
  // A height, standing where the capture has a calibration frame.
  const auto height_ratio = [&](const std::string& landmark) {
    const double standing = options.stature ? HeightRatioAboveFeet(*options.stature, robot, landmark, 0) : std::nan("");
    return std::isfinite(standing) ? standing : HeightRatioAboveFeet(landmarks, robot, landmark, reference);
  };
  if (options.per_chain && !std::isfinite(legs)) {
    legs = height_ratio("pelvis");
    if (std::isfinite(legs)) notes.push_back("could not measure the legs (hip, knee and foot landmarks, foot tasks): legs "
                                             "scaled by the pelvis height above the feet");
  }
  if (!std::isfinite(legs)) {
    legs = height_ratio("head");
    if (!std::isfinite(legs)) notes.push_back("could not measure heights (head and feet tasks needed): scale 1");
    else if (options.per_chain) notes.push_back("no pelvis height above the feet: every landmark scaled by the head's height");
  }
  alignment.leg_scale = std::isfinite(legs) ? legs : 1.0;
  alignment.arm_scale = alignment.leg_scale;
  if (!options.per_chain) return alignment;
  alignment.pelvis = LandmarkIndex(landmarks, "pelvis");
  if (alignment.pelvis >= 0) alignment.pelvis_reference = SampleAt(landmarks, reference, alignment.pelvis);
  const double arms = ArmRatio(landmarks, robot, reference);
  if (std::isfinite(arms) && alignment.pelvis >= 0 && alignment.pelvis_reference.valid) {
    alignment.arm_scale = arms;
    for (const char* side : kSides) {
      for (const char* part : {"_elbow", "_hand"}) {
        const int64_t index = LandmarkIndex(landmarks, std::string(side) + part);
        if (index >= 0) alignment.on_arm[static_cast<size_t>(index)] = true;
      }
    }
  } else {
    notes.push_back("could not measure the arms (shoulder, elbow and hand landmarks, hand and elbow tasks, a pelvis): "
                    "arms scaled as the legs");
  }
  return alignment;
}

Eigen::Vector3d RobotDisplacement(const StanceAlignment& alignment, const LandmarkTrajectories& landmarks,
                                  int64_t landmark, int64_t t, const LandmarkSample& sample,
                                  const LandmarkSample& reference) {
  if (alignment.on_arm[static_cast<size_t>(landmark)]) {
    const LandmarkSample pelvis = SampleAt(landmarks, t, alignment.pelvis);
    if (pelvis.valid) {
      const Eigen::Vector3d& pelvis_reference = alignment.pelvis_reference.position;
      return alignment.heading * (alignment.leg_scale * (pelvis.position - pelvis_reference) +
                                  alignment.arm_scale * ((sample.position - pelvis.position) -
                                                         (reference.position - pelvis_reference)));
    }
  }
  return alignment.leg_scale * (alignment.heading * (sample.position - reference.position));
}

std::vector<LandmarkSample> NeutralReference(const LandmarkTrajectories& landmarks, int64_t reference,
                                             const std::vector<int64_t>& tracked, const std::vector<bool>& neutral) {
  std::vector<LandmarkSample> samples;
  for (int64_t landmark : tracked) samples.push_back(SampleAt(landmarks, reference, landmark));
  const int64_t pelvis = LandmarkIndex(landmarks, "pelvis");
  if (pelvis < 0) return samples;
  const LandmarkSample pelvis_at_reference = SampleAt(landmarks, reference, pelvis);
  if (!pelvis_at_reference.valid) return samples;
  // Per frame, the pelvis and its turn about the vertical since the reference frame.
  std::vector<LandmarkSample> pelvis_at(static_cast<size_t>(landmarks.frames));
  std::vector<Eigen::Matrix3d> unturn(static_cast<size_t>(landmarks.frames), Eigen::Matrix3d::Identity());
  for (int64_t t = 0; t < landmarks.frames; ++t) {
    const LandmarkSample& at = pelvis_at[static_cast<size_t>(t)] = SampleAt(landmarks, t, pelvis);
    if (!at.valid || !at.has_orientation || !pelvis_at_reference.has_orientation) continue;
    const Eigen::Vector3d forward = (at.orientation * pelvis_at_reference.orientation.conjugate()) * Eigen::Vector3d::UnitX();
    unturn[static_cast<size_t>(t)] = Eigen::AngleAxisd(-std::atan2(forward.y(), forward.x()), Eigen::Vector3d::UnitZ()).toRotationMatrix();
  }
  std::array<std::vector<double>, 3> offsets;
  for (size_t i = 0; i < tracked.size(); ++i) {
    if (!neutral[i] || tracked[i] == pelvis || !samples[i].valid) continue;
    for (auto& axis : offsets) axis.clear();
    for (int64_t t = 0; t < landmarks.frames; ++t) {
      const LandmarkSample& pelvis_now = pelvis_at[static_cast<size_t>(t)];
      const LandmarkSample at = SampleAt(landmarks, t, tracked[i]);
      if (!pelvis_now.valid || !at.valid) continue;
      const Eigen::Vector3d offset = unturn[static_cast<size_t>(t)] * (at.position - pelvis_now.position);
      for (int axis = 0; axis < 3; ++axis) offsets[static_cast<size_t>(axis)].push_back(offset(axis));
    }
    if (offsets[0].empty()) continue;
    for (int axis = 0; axis < 3; ++axis) {
      samples[i].position(axis) = pelvis_at_reference.position(axis) + NearestRankPercentile(offsets[static_cast<size_t>(axis)], 0.5);
    }
  }
  // An arm raised at the reference frame far above where it mostly is (a walk that starts in a T-pose) is
  // measured from a frame where it is as it mostly is, moved to the reference frame's pelvis and heading.
  std::vector<bool> usable(static_cast<size_t>(landmarks.frames));
  for (int64_t t = 0; t < landmarks.frames; ++t) usable[static_cast<size_t>(t)] = pelvis_at[static_cast<size_t>(t)].valid;
  const int64_t upper_torso = LandmarkIndex(landmarks, "upper_torso");
  for (const char* side : kSides) {
    const std::string prefix = side;
    const int64_t hand = LandmarkIndex(landmarks, prefix + "_hand");
    const int64_t shoulder_landmark = LandmarkIndex(landmarks, prefix + "_shoulder");
    const int64_t shoulder = shoulder_landmark >= 0 ? shoulder_landmark : upper_torso;
    if (hand < 0 || shoulder < 0) continue;
    const int64_t typical = TypicalArmFrame(landmarks, reference, hand, shoulder, usable);
    if (typical == reference) continue;
    const Eigen::Matrix3d& turn = unturn[static_cast<size_t>(typical)];
    const Eigen::Vector3d& pelvis_then = pelvis_at[static_cast<size_t>(typical)].position;
    for (size_t i = 0; i < tracked.size(); ++i) {
      const std::string& name = landmarks.names[static_cast<size_t>(tracked[i])];
      if (name != prefix + "_hand" && name != prefix + "_elbow") continue;
      const LandmarkSample at = SampleAt(landmarks, typical, tracked[i]);
      if (!at.valid) continue;
      samples[i] = at;
      samples[i].position = pelvis_at_reference.position + turn * (at.position - pelvis_then);
      samples[i].orientation = Eigen::Quaterniond(turn) * at.orientation;
    }
  }
  return samples;
}

}  // namespace syn
