#include "stages/archive/joint_markers.h"

#include <algorithm>

namespace syn {

BvhConvention DetectBvhConvention(const std::vector<std::string>& bodies) {
  auto has = [&](const char* name) { return std::find(bodies.begin(), bodies.end(), name) != bodies.end(); };
  if (has("LeftUpLeg") && has("LeftToeBase")) return BvhConvention::kMotionBuilder;
  if (has("LeftHip") && has("LeftToe")) return BvhConvention::kMax;
  return BvhConvention::kNone;
}

const std::array<JointMarker, 22>& SmplJointMarkers() {
  static const std::array<JointMarker, 22> markers = {{
      {"pelvis", "pelvis", {"Hips", "Hips"}},
      {"left_hip", "right_hip", {"LeftUpLeg", "LeftHip"}},
      {"right_hip", "left_hip", {"RightUpLeg", "RightHip"}},
      {"spine1", "spine1", {"Spine", "Chest"}},
      {"left_knee", "right_knee", {"LeftLeg", "LeftKnee"}},
      {"right_knee", "left_knee", {"RightLeg", "RightKnee"}},
      {"spine2", "spine2", {"Spine1", "Chest2"}},
      {"left_ankle", "right_ankle", {"LeftFoot", "LeftAnkle"}},
      {"right_ankle", "left_ankle", {"RightFoot", "RightAnkle"}},
      {"spine3", "spine3", {"Spine1", "Chest2"}},
      {"left_foot", "right_foot", {"LeftToeBase", "LeftToe"}},
      {"right_foot", "left_foot", {"RightToeBase", "RightToe"}},
      {"neck", "neck", {"Neck1", "Neck"}},
      {"left_collar", "right_collar", {"LeftArm", "LeftShoulder"}},
      {"right_collar", "left_collar", {"RightArm", "RightShoulder"}},
      {"head", "head", {"Head", "Head"}},
      {"left_shoulder", "right_shoulder", {"LeftArm", "LeftShoulder"}},
      {"right_shoulder", "left_shoulder", {"RightArm", "RightShoulder"}},
      {"left_elbow", "right_elbow", {"LeftForeArm", "LeftElbow"}},
      {"right_elbow", "left_elbow", {"RightForeArm", "RightElbow"}},
      {"left_wrist", "right_wrist", {"LeftHand", "LeftWrist"}},
      {"right_wrist", "left_wrist", {"RightHand", "RightWrist"}},
  }};
  return markers;
}

}  // namespace syn
