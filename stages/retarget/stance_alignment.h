// How a capture's landmark displacements become the robot's: turned so the subject faces +X, and scaled.
//
// A landmark's target is its robot link's pose in the reference stance plus the landmark's displacement since
// the reference frame, turned and scaled. Two ways to scale (issue 17, item 3):
//   * height (the default): one robot / subject ratio of the head's height above the feet for everything;
//   * per chain (--proportions chains, or the robot map's proportions = "chains"): the pelvis, the feet, the
//     trunk and the head move by leg_scale = robot / subject leg length, hip to ankle (the robot's from its
//     URDF, the subject's hip–knee–ankle from the marker set's hip and knee landmarks; without them the
//     pelvis height above the feet at the reference); the elbows and hands move with the pelvis (leg_scale) plus their motion relative to it
//     scaled by arm_scale = robot / subject arm length, shoulder–elbow–hand (the robot's from its URDF, the
//     subject's from the marker set's shoulder landmarks; without them the arms move as the legs).
// Why both: the G1 map's "head" link sits at its waist, so its height ratio is 0.54-0.64 on CMU subjects
// against leg ratios of 0.76-0.82 — strides and pelvis heights shrunk by a quarter. Per chain is the
// faithful proportion, but at full-length strides the contact enforcement does not yet keep flat planted
// feet still on the G1 (32 CMU walks and dances: drift bounds met on 18, was 24), so it is not yet the default.
// Legs by their length, not the pelvis height: the pelvis link is not at the same place on every robot —
// HRP-4C's hip_base is 0.197 m above its hip joints, the G1's pelvis 0.10 m, CMU's Hips 0.10 m — and a
// reference frame mid-stride or crouched lowers the subject's pelvis. On HRP-4C (leg 0.69 m) the pelvis
// heights gave 1.01-1.3 on CMU subjects whose legs are 0.80-0.87 m (0.80-0.86 by length), and the head
// height 0.93-1.2: HRP-4C's neck stands as high as a CMU subject's, on shorter legs. Strides scaled by it
// outreach its legs, the base was lowered 10-14 cm, and its planted feet drifted 11-302 mm per phase.
// With --scale every landmark moves by the one given ratio.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "common/model.h"
#include "stages/retarget/landmarks.h"

namespace syn {

struct StanceAlignment {
  Eigen::Matrix3d heading = Eigen::Matrix3d::Identity();  // capture -> robot turn about the vertical
  double heading_rad = 0.0;
  double leg_scale = 1.0;
  double arm_scale = 1.0;
  std::vector<bool> on_arm;                 // per landmark: moves relative to the pelvis by arm_scale
  int64_t pelvis = -1;                      // the pelvis landmark (-1: the marker set has none)
  LandmarkSample pelvis_reference;          // the pelvis at the reference frame
};

// What the alignment needs to know about the robot in its reference stance.
struct RobotStance {
  // Per tracked task: its landmark's name and its link's pose in the reference stance.
  std::vector<std::string> task_landmarks;
  std::vector<Eigen::Isometry3d> link_reference;
  // Per side (left, right; NaN when the map does not track that arm): shoulder–elbow + elbow–hand, metres.
  double arm_length[2] = {std::nan(""), std::nan("")};
  // Per side, as arm_length: hip (the first joint below where the feet's chains part) to the foot task's link.
  double leg_length[2] = {std::nan(""), std::nan("")};
};

// The robot's arm lengths for RobotStance: from the joint where the two hand links' chains part (the
// shoulder's first joint) to the elbow task's link, plus on to the hand task's link, at the workspace's pose.
// `task_links`: the link of each of stance.task_landmarks.
void MeasureRobotArms(const Model& model, Workspace& workspace, const std::vector<std::string>& task_links,
                      RobotStance& stance);

// The robot's leg lengths for RobotStance: the straight distance from the hip (the first link below where the
// two foot links' chains part) to the foot task's link at the workspace's pose — the leg's length when the
// reference stance stands straight-legged, as both maps' do (a bent one would measure it short).
void MeasureRobotLegs(const Model& model, Workspace& workspace, const std::vector<std::string>& task_links,
                      RobotStance& stance);

struct AlignmentOptions {
  double fixed_scale = 0.0;          // > 0: one scale for every landmark
  bool per_chain = false;            // legs and arms by their own lengths (above)
  bool heading_from_pelvis = false;  // RetargetOptions::heading_from_pelvis, when no --reference-time is given
  // Non-null: the subject's heights (head or pelvis above the feet) are measured at its frame 0, a standing
  // calibration frame, instead of at the reference frame; the reference frame where it lacks a landmark.
  const LandmarkTrajectories* stature = nullptr;
};

[[nodiscard]] StanceAlignment AlignToRobot(const LandmarkTrajectories& landmarks, const RobotStance& robot,
                                           int64_t reference, const AlignmentOptions& options,
                                           std::vector<std::string>& notes);

// The source's reference for `tracked` landmarks when the reference is a frame of the take (no calibration
// frame, no --reference-time): those marked `neutral` (the feet) at the pelvis landmark's reference position plus
// their median offset from the pelvis over the take — measured in the pelvis's heading at each frame,
// turned to the reference frame's heading (world axes when the pelvis has no orientation) —, the others at
// the reference frame. The robot's reference stance stands with its feet under its hips; a walk's first
// frame is mid-stride, and measuring from it left one foot 0.19 m behind the pelvis for the whole take (CMU
// 02_01 onto G1): the planted foot out of reach at every push-off, the base lowered 10 cm for it, a crouched
// walk. The arms keep the reference frame: the G1's reference holds its forearms forward, not hanging as a
// walker's median does, and their median swing put its hands at the edge of reach (elbow on its limit).
// But an arm raised at the reference frame more than 45° above its median over the take (the elevation of
// the hand from straight down, seen from its shoulder landmark, or the upper torso's) is taken from the
// take's first frame at or below that median, moved to the reference frame's pelvis and heading. CMU 03_02
// starts in a T-pose, and measured from it every hanging hand of the walk was a displacement 0.45 m inwards
// and 0.37 m down: HRP-4C's hands crossed its body at its knees (P1 error median 163 mm) and it crouched for
// them (its right plant drifting 72 mm). (syn-ingest now drops 03_02's T-pose lead-in, bvh_reader.cpp; the rule
// stays for takes that begin in a T-pose without a jump.) A dance that holds its arms out most of the time (CMU 94_06, 94_13)
// keeps its reference: from hanging arms, its raised ones put the G1's hands, whose reference holds the
// forearms forward, out of reach (P1 hand error median 28 -> 103 mm on 94_13).
// Without a pelvis landmark every landmark keeps the reference frame.
[[nodiscard]] std::vector<LandmarkSample> NeutralReference(const LandmarkTrajectories& landmarks, int64_t reference,
                                                           const std::vector<int64_t>& tracked,
                                                           const std::vector<bool>& neutral);

// The robot-frame displacement of `landmark` at frame t: `sample` is it at t, `reference` at the reference.
[[nodiscard]] Eigen::Vector3d RobotDisplacement(const StanceAlignment& alignment, const LandmarkTrajectories& landmarks,
                                                int64_t landmark, int64_t t, const LandmarkSample& sample,
                                                const LandmarkSample& reference);

}  // namespace syn
