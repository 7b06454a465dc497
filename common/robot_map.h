// Robot maps (manifests/robots/NAME.toml): which robot link tracks which
// landmark, how (pose / orientation / position), at which priority, and the
// robot's reference stance and foot soles.
//
// Defaults follow the paper's Table I: priority 1 pelvis, feet and hands
// pose, head orientation; priority 2 upper torso and elbows orientation;
// priority 3 joint posture toward the reference stance. The retargeter's
// least-squares IK realises priorities as weights: a task's residual is
// multiplied by priority_weights[level - 1] × weight (defaults 1, 0.1, 0.001:
// level 2 counts 100× less than level 1 in the squared cost, the posture
// 10⁶× less, so it only settles what the tasks leave free — with 0.01 it
// measurably pulled G1's links off exact targets: 0.45 mm RMS against
// 0.03 mm in the ground-truth test).
#pragma once

#include <array>
#include <functional>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace syn {

enum class TaskType { kPose, kOrientation, kPosition };

struct RobotTask {
  std::string landmark;  // one of kLandmarkNames
  std::string link;      // URDF link name
  TaskType type = TaskType::kPose;
  int priority = 1;      // 1 (highest) .. 3
  double weight = 1.0;
  int line = 0;
};

struct RobotFoot {
  std::string side;  // "left" or "right"
  std::string link;
  std::vector<std::array<double, 3>> sole_points;  // in the link frame, metres
  int line = 0;
};

struct RobotMap {
  std::string file;
  std::string robot;
  std::string floating_base = "auto";
  // How the retargeter scales a capture onto this robot unless told (--proportions): "height" or "chains"
  // (stages/retarget/stance_alignment.h).
  std::string proportions = "height";
  // rad: how far a planted foot may pitch with the source about its heel or toe edge (heel strike, toe-off)
  // instead of lying flat, unless told (--max-roll); 0: flat (stages/retarget/contact_enforcement.h).
  double max_roll = 0.0;
  // s: the half-width of the smoothing of the pelvis moves contact enforcement makes for plants, unless told
  // (--base-smoothing): shorter for a robot whose legs are slow to follow a pelvis that moves for them late
  // (stages/retarget/contact_enforcement.h).
  double base_smoothing = 0.1;
  // The fraction of the URDF velocity limits each frame's joint step is bounded by unless told
  // (--velocity-limit-scale; 0: unbounded): above 1 where a person's pace needs more than the URDF allows and
  // the contacts are to rank above the motors' speed (stages/retarget/retarget.h).
  double velocity_limit_scale = 1.0;
  std::vector<RobotTask> tasks;
  std::array<double, 3> priority_weights = {1.0, 0.1, 0.001};
  int posture_priority = 3;
  double posture_weight = 1.0;
  std::map<std::string, double> reference_stance;  // joint name -> q (rad or m); others 0
  // The pose captures take in their calibration frame (a T-pose), as joint -> q like reference_stance; when
  // the map has [calibration_stance] and a capture carries that frame (MarkerData::calibration_body_pose),
  // the capture is retargeted relative to it rather than to a frame of the take. reference_stance stays
  // the posture target.
  std::optional<std::map<std::string, double>> calibration_stance;  // an empty table is the default pose
  std::vector<RobotFoot> feet;
  // [joint_ranges]: joint -> [lower, upper], narrowing the URDF's limits for retargeting (a range the robot
  // has but a person never uses, through which the IK can reach a mirrored solution: G1's hip roll to 170°).
  std::map<std::string, std::array<double, 2>> joint_ranges;
  int joint_ranges_line = 0;
};

[[nodiscard]] std::string TaskTypeName(TaskType type);

[[nodiscard]] RobotMap LoadRobotMap(const std::string& path);
[[nodiscard]] RobotMap ParseRobotMap(const std::string& toml_text, const std::string& file_name);

// Checks every link and joint name against the model: `has_link(name)`,
// `has_joint(name)`. A missing one is a DataError at the map's line.
void CheckRobotMapNames(const RobotMap& map, const std::function<bool(const std::string&)>& has_link,
                        const std::function<bool(const std::string&)>& has_joint, const std::string& model_name);

}  // namespace syn
