// syn-retarget: landmark trajectories of a capture -> a humanoid motion
// (q, u, udot, tau) by per-frame IK, a trajectory refinement and Simbody
// inverse dynamics.
//
// The steps (retarget.cpp): pick the robot map's tasks the capture can feed;
// find the reference stance; place the robot's reference stance on the ground;
// turn and scale the capture to the robot; solve every frame; bridge short
// gaps; refine the trajectory; measure the landmark errors; compute
// velocities, accelerations and torques.
#pragma once

#include <array>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Geometry>
#include <nlohmann/json.hpp>

#include "common/marker_data.h"
#include "common/marker_set.h"
#include "common/model.h"
#include "common/motion_file.h"
#include "common/robot_map.h"
#include "stages/retarget/contact_detection.h"
#include "stages/retarget/floor_levelling.h"
#include "stages/retarget/contact_enforcement.h"
#include "common/contact_forces.h"

namespace syn {

// Which floating base the robot gets: the robot map's choice, or one named here (common/model.h).
enum class FloatingBaseChoice { kFromMap, kAuto, kFree, kFixed };
[[nodiscard]] const char* FloatingBaseChoiceName(FloatingBaseChoice choice);
// "map", "auto", "free" or "fixed"; false for anything else.
[[nodiscard]] bool ParseFloatingBaseChoice(const std::string& text, FloatingBaseChoice* choice);

struct RetargetOptions {
  std::string model;          // URDF
  std::string robot_map;      // manifests/robots/NAME.toml
  std::string markerset;      // manifests/markersets/NAME.toml
  FloatingBaseChoice floating_base = FloatingBaseChoice::kFromMap;
  // Reference stance: the first frame at which every tracked landmark is present, or the frame nearest
  // this time (s) if >= 0.
  double reference_time = -1.0;
  // One robot/subject ratio for every landmark displacement; 0 = measured (stance_alignment.h).
  double scale = 0.0;
  // Measured per chain (legs by hip–knee–ankle length, arms by shoulder–elbow–hand length) instead of one
  // head-height ratio (stance_alignment.h says why it is not yet the default); unset: the robot map's
  // proportions.
  std::optional<bool> proportions_per_chain;
  // rad: contact enforcement's max_roll; unset: the robot map's max_roll.
  std::optional<double> max_roll;
  // s: contact enforcement's base_smoothing; unset: the robot map's base_smoothing.
  std::optional<double> base_smoothing;
  // Frames with no target at all are bridged when the gap is at most this long (s).
  double max_bridge = 0.25;
  // Each frame's joint step is bounded by this fraction of the URDF velocity limit times the time since
  // the previous solved frame (0 = unbounded): the robot cannot follow a target faster than its motors,
  // and the IK cannot jump to another branch of its solutions between two frames. Unset: the robot map's
  // velocity_limit_scale (1 unless it says).
  std::optional<double> velocity_limit_scale;
  // Weight of accelerations in the trajectory refinement (trajectory_refinement.h); 0 = per-frame IK only.
  double smoothing = 1.0;
  // Multiplies the robot map's posture weight. Joint centres alone (no segment orientations, e.g.
  // humanml3d22) leave each arm's swivel and wrist free; with the map's posture weight they drift over
  // minutes until joints pin on their limits, and 10 holds them (archive walk trial: P1 81 -> 14 mm).
  double posture_scale = 1.0;
  // The per-frame IK stops when an iteration changes the cost by less than this fraction (Ceres
  // function_tolerance; frame_ik.h says why 1e-3: tighter values spent 5-10 more, mostly rejected,
  // iterations per frame on real captures for no change in their landmark errors).
  double ik_function_tolerance = 1e-3;
  // The source's foot contacts (contact_detection.h: thresholds and their sources): stored in the motion
  // and measured on the result (stance drift, penetration, foot skating).
  ContactDetectionOptions contact;
  // The take turned so its floor, fitted to the standing feet, is level (floor_levelling.h).
  FloorLevellingOptions floor;
  // On a take whose stances fit no floor (uneven terrain), the raised plants and the body above them
  // lowered onto the robot's flat floor (terrain_flattening.h).
  bool flatten_terrain = true;
  // Each foot's orientation target held within the turn about the pelvis its leg's joints can make
  // (foot_yaw_range.h): a capture's foot that swivels further is not followed by contorting the leg.
  bool hold_foot_yaw = true;
  // Contacts as constraints above every task (contact_enforcement.h): planted soles flat on the floor and
  // still, no sole point below it, the base lowered where a planted leg cannot reach. false: measured only.
  bool enforce_contacts = true;
  // The heading from the pelvis frame averaged over the capture instead of the feet's and elbows'
  // left-right vector at the reference frame, which mid-stride is turned by the stride (the demo walk went
  // 40° crabwise, and planted feet then cannot lie flat).
  bool heading_from_pelvis = true;
  // The feet measured from their median offset to the pelvis over the take rather than from
  // the reference frame's (stance_alignment.h NeutralReference), when the reference is a frame of the take.
  bool neutral_reference = true;
  ContactEnforcementOptions enforcement;
  // The base's residual split into contact forces at the planted soles (contact_forces.h).
  ContactForceOptions contact_forces;

  // The input files given and every value in range.
  bool IsValid(std::string* error) const;
  // Every value in range (what `--print-parameters` checks: the files are inputs, not parameters).
  bool HasValidValues(std::string* error) const;
  nlohmann::json ToJson() const;
};

struct RetargetSummary {
  int64_t frames = 0;
  int64_t reference_frame = 0;  // -1: the capture's calibration frame (RobotMap::stance_is_calibration_pose)
  double scale = 1.0;      // the legs' (stance_alignment.h): pelvis, feet, trunk and head
  double arm_scale = 1.0;  // the elbows' and hands' motion relative to the pelvis
  double heading_rad = 0.0;
  double floor_tilt_rad = 0.0;  // the capture's floor plane against the horizontal (floor_levelling.h)
  bool floor_levelled = false;  // and whether the take was turned level
  Eigen::Quaterniond floor_rotation = Eigen::Quaterniond::Identity();  // how (about a point on the floor)
  // Per priority level 1..3: median and 95th percentile of position (m) and angle (rad) errors.
  std::array<double, 3> median_position_error{}, p95_position_error{}, median_angle_error{}, p95_angle_error{};
  double worst_joint_step = 0.0;        // largest per-frame |Δq| of any joint (rad)
  std::string worst_joint_step_name;
  double ik_seconds = 0.0;
  double refinement_seconds = 0.0;
  double mean_ik_iterations = 0.0;
  std::vector<std::string> notes;
  // What a user checks, from the robot's sole points (the robot map's feet) on the final motion:
  std::vector<std::string> foot_sides;         // the robot map's feet, in the contact columns' order
  std::vector<int64_t> contact_frames;         // per foot, frames the source's foot is planted
  std::vector<ContactPhase> contact_phases;    // the source's contact phases
  std::vector<double> phase_drift;             // per phase, the sole centre's largest horizontal drift (m)
  double median_drift = 0.0, p95_drift = 0.0, max_drift = 0.0;
  double deepest_penetration = 0.0;            // m below z = 0 (0 when never below)
  int64_t deepest_frame = -1;
  double penetrating_fraction = 0.0;           // frames with a sole point more than 1 cm below the floor
  double foot_skating = 0.0;                   // GMD foot-skating ratio of the robot's soles
  double source_foot_skating = 0.0;            // the same on the source's foot targets with the robot's soles
  bool contacts_enforced = false;
  ContactEnforcementReport enforcement;        // what enforcing the contacts took
  // The base's residual wrench and what the planted soles' admissible forces leave of it, mean magnitude
  // over the frames (N, N·m about the centre of mass); forces_split is false without feet or a base.
  bool forces_split = false;
  double mean_residual_force = 0, mean_residual_moment = 0, mean_unexplained_force = 0, mean_unexplained_moment = 0;

  std::string BriefReport() const;
};

// Everything a retargeting run reads from files, loaded and checked against each other (the map's links
// and joints exist in the model).
struct RetargetInputs {
  std::string capture_path;
  MarkerData capture;
  MarkerSet marker_set;
  RobotMap map;
  Model model;
};

[[nodiscard]] RetargetInputs LoadRetargetInputs(const std::string& markers_path, const RetargetOptions& options);

// The motion of `inputs.model` that tracks the capture's landmarks. `workspace` belongs to that model.
[[nodiscard]] MotionData Retarget(const RetargetInputs& inputs, Workspace& workspace, const RetargetOptions& options,
                                  RetargetSummary* summary);

// LoadRetargetInputs, then Retarget (tests and benchmarks).
[[nodiscard]] MotionData RetargetFile(const std::string& markers_path, const RetargetOptions& options,
                                      RetargetSummary* summary);

}  // namespace syn
