#include "tools/archive/joint_markers.h"

#include <algorithm>

namespace syn {

BvhConvention DetectBvhConvention(const std::vector<std::string>& bodies) {
  auto has = [&](const char* name) { return std::find(bodies.begin(), bodies.end(), name) != bodies.end(); };
  if (has("LeftUpLeg") && has("LeftToeBase")) return BvhConvention::kMotionBuilder;
  if (has("LeftHip") && has("LeftToe")) return BvhConvention::kMax;
  if (has("hip") && has("lThigh") && has("lFoot_end")) return BvhConvention::kDaz;
  return BvhConvention::kNone;
}

const std::array<JointMarker, 22>& SmplJointMarkers() {
  static const std::array<JointMarker, 22> markers = {{
      {"pelvis", "pelvis", {"Hips", "Hips", "hip"}},
      {"left_hip", "right_hip", {"LeftUpLeg", "LeftHip", "lThigh"}},
      {"right_hip", "left_hip", {"RightUpLeg", "RightHip", "rThigh"}},
      {"spine1", "spine1", {"Spine", "Chest", "abdomen"}},
      {"left_knee", "right_knee", {"LeftLeg", "LeftKnee", "lShin"}},
      {"right_knee", "left_knee", {"RightLeg", "RightKnee", "rShin"}},
      {"spine2", "spine2", {"Spine1", "Chest2", "chest"}},
      {"left_ankle", "right_ankle", {"LeftFoot", "LeftAnkle", "lFoot"}},
      {"right_ankle", "left_ankle", {"RightFoot", "RightAnkle", "rFoot"}},
      {"spine3", "spine3", {"Spine1", "Chest2", "chest"}},
      {"left_foot", "right_foot", {"LeftToeBase", "LeftToe", "lFoot_end"}},
      {"right_foot", "left_foot", {"RightToeBase", "RightToe", "rFoot_end"}},
      {"neck", "neck", {"Neck1", "Neck", "neck"}},
      {"left_collar", "right_collar", {"LeftArm", "LeftShoulder", "lCollar"}},
      {"right_collar", "left_collar", {"RightArm", "RightShoulder", "rCollar"}},
      {"head", "head", {"Head", "Head", "head"}},
      {"left_shoulder", "right_shoulder", {"LeftArm", "LeftShoulder", "lShldr"}},
      {"right_shoulder", "left_shoulder", {"RightArm", "RightShoulder", "rShldr"}},
      {"left_elbow", "right_elbow", {"LeftForeArm", "LeftElbow", "lForeArm"}},
      {"right_elbow", "left_elbow", {"RightForeArm", "RightElbow", "rForeArm"}},
      {"left_wrist", "right_wrist", {"LeftHand", "LeftWrist", "lHand"}},
      {"right_wrist", "left_wrist", {"RightHand", "RightWrist", "rHand"}},
  }};
  return markers;
}

}  // namespace syn
