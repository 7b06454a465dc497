// syn-retarget: landmark trajectories of a capture -> a humanoid motion
// (q, u, udot, tau) by per-frame IK and Simbody inverse dynamics.
#pragma once

#include <array>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/motion_file.h"

namespace syn {

struct RetargetOptions {
  std::string model;          // URDF
  std::string robot_map;      // manifests/robots/NAME.toml
  std::string markerset;      // manifests/markersets/NAME.toml
  std::string floating_base = "map";  // "map" = as the robot map says; or auto | free | fixed
  // Reference stance: the first frame at which every tracked landmark is
  // present, or the frame nearest this time (s) if >= 0.
  double reference_time = -1.0;
  // Robot height / subject height for landmark displacements; "auto" measures
  // both (vertical distance from the feet to the head landmark).
  std::string scale = "auto";
  // Frames with no target at all are bridged when the gap is at most this long (s).
  double max_bridge = 0.25;
  // Each frame's joint step is bounded by this fraction of the URDF velocity limit times the time since
  // the previous solved frame (0 = unbounded): the robot cannot follow a target faster than its motors,
  // and the IK cannot jump to another branch of its solutions between two frames.
  double velocity_limit_scale = 1.0;
  // Weight of accelerations in the trajectory refinement (trajectory_refinement.h); 0 = per-frame IK only.
  double smoothing = 1.0;
  // Multiplies the robot map's posture weight. Joint centres alone (no segment orientations, e.g.
  // humanml3d22) leave each arm's swivel and wrist free; with the map's posture weight they drift over
  // minutes until joints pin on their limits, and 10 holds them (archive walk trial: P1 81 -> 14 mm).
  double posture_scale = 1.0;

  bool IsValid(std::string* error) const;
  nlohmann::json ToJson() const;
};

struct RetargetSummary {
  int64_t frames = 0;
  int64_t reference_frame = 0;
  double scale = 1.0;
  double heading_rad = 0.0;
  // Per priority level 1..3: median and 95th percentile of position (m) and angle (rad) errors.
  std::array<double, 3> median_position_error{}, p95_position_error{}, median_angle_error{}, p95_angle_error{};
  double worst_joint_step = 0.0;        // largest per-frame |Δq| of any joint (rad)
  std::string worst_joint_step_name;
  double ik_seconds = 0.0;
  double refinement_seconds = 0.0;
  double mean_ik_iterations = 0.0;
  std::vector<std::string> notes;

  std::string BriefReport() const;
};

[[nodiscard]] MotionData Retarget(const std::string& markers_path, const RetargetOptions& options,
                                  RetargetSummary* summary);

}  // namespace syn
