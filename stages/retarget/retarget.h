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
#include <cmath>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/marker_data.h"
#include "common/marker_set.h"
#include "common/model.h"
#include "common/motion_file.h"
#include "common/robot_map.h"
#include "stages/retarget/contact_detection.h"

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
  // Robot/subject ratio for every landmark displacement; 0 = measure at the reference stance: the
  // head-to-feet height ratio, or with chain_proportions per kinematic chain — legs (pelvis and feet) by
  // the hip-to-ankle height ratio, hands (relative to the pelvis) by the torso-to-hand ratio, anything
  // else by the height ratio.
  double scale = 0.0;
  // With scale 0: true scales per kinematic chain as above; false (default) every displacement by the
  // height ratio. Off by default because the chain ratios are measured at the reference frame, which on
  // most captures is not a standing pose (the first frame of a walk is mid-stride), and the legs' larger
  // ratio then asks the pelvis to rise above the robot's straight legs: on CMU 02_01 onto the G1 (legs
  // 0.863, height 0.589) P1 went from 38/151 to 71/250 mm median/p95 with contacts.
  bool chain_proportions = false;
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
  // The per-frame IK stops when an iteration changes the cost by less than this fraction (Ceres
  // function_tolerance; frame_ik.h says why 1e-3: tighter values spent 5-10 more, mostly rejected,
  // iterations per frame on real captures for no change in their landmark errors).
  double ik_function_tolerance = 1e-3;
  // Foot contacts of the source (contact_detection.h: thresholds and their sources). While a source foot
  // is planted the robot's foot is held flat on the floor at its touchdown pose, and every sole point
  // stays at z >= 0 in every frame: exact constraints above every task. false: no contact constraints.
  bool contacts = true;
  // Exact contact constraints on top of the shaped targets: the planted foot held exactly at its pose and
  // every sole point at z >= 0 in every frame, by constrained Gauss–Newton steps after each frame's
  // solve, a heavy linearised term in the refinement and a final per-frame projection. Off by default:
  // on the demo walk (CMU 02_01 onto the G1) they took the deepest sole point from 9.7 mm to 0 but made
  // the base's acceleration p95 12 -> 200+ m/s² (a constrained step per frame is not smooth in time)
  // and the stage 3x slower; the shaped targets alone keep penetration and stance drift within the
  // tolerances a user checks.
  bool exact_contacts = false;
  // With --contacts: lower the upper body where a foot target is out of its leg's reach (leg_reach.h).
  bool leg_reach = true;
  ContactDetectionOptions contact;
  // At a lift-off, every task's error at the last planted frame is carried into its target and decays
  // to zero over this time (s, smoothstep), so what the planted foot held back does not jump to its
  // target in one frame. 0.2 s: about half a walking swing phase; a 20 cm carried error then peaks at
  // 30 m/s², where releasing it in one 120 Hz frame asked thousands.
  double contact_blend = 0.2;
  // A foot's target blends into its planted pose over this time before a touchdown and out of it after a
  // lift-off (s; foot_targets.h says why 0.1 s). 0: the targets switch in one frame.
  double contact_approach = 0.1;

  bool IsValid(std::string* error) const;
  nlohmann::json ToJson() const;
};

struct RetargetSummary {
  int64_t frames = 0;
  int64_t lowered_frames = 0;      // frames whose upper body was lowered into the legs' reach (leg_reach.h)
  double largest_drop = 0.0;       // m
  int64_t unreachable_frames = 0;  // frames with a foot target horizontally out of its leg's reach
  int64_t reference_frame = 0;
  double scale = 1.0;      // robot/subject height
  double leg_scale = 1.0;  // robot/subject hip-to-ankle height: the pelvis's and feet's displacements
  double arm_scale = 1.0;  // robot/subject torso-to-hand distance: the hands' displacements from the pelvis
  double heading_rad = 0.0;
  // Per priority level 1..3: median and 95th percentile of position (m) and angle (rad) errors.
  std::array<double, 3> median_position_error{}, p95_position_error{}, median_angle_error{}, p95_angle_error{};
  double worst_joint_step = 0.0;        // largest per-frame |Δq| of any joint (rad)
  std::string worst_joint_step_name;
  double ik_seconds = 0.0;
  double refinement_seconds = 0.0;
  double mean_ik_iterations = 0.0;
  // Contacts: per robot foot (the map's order), its side, the source's contact frames and phases, and on the
  // final motion each phase's stance drift (the largest horizontal distance, m, of the foot link from its
  // touchdown position); the deepest sole point (m below z = 0, 0 if none) and its frame; the frames where
  // the constraints could not be met exactly (joint limits, velocity bound).
  std::vector<std::string> foot_sides;
  std::vector<int64_t> contact_frames;
  std::vector<ContactPhase> contact_phases;
  std::vector<double> phase_drift;
  double median_drift = 0.0, p95_drift = 0.0, max_drift = 0.0;
  double deepest_penetration = 0.0;
  double penetrating_fraction = 0.0;   // frames with a sole point more than 1 cm below the floor
  double foot_skating = 0.0;           // GMD foot-skating ratio of the robot's soles
  double source_foot_skating = 0.0;    // the same measure on the source's foot targets
  int64_t deepest_frame = -1;
  int64_t constraint_violations = 0;
  // Median over frames of the base residual no admissible contact force explains (free base only; NaN otherwise).
  double median_unexplained_force = std::nan(""), median_unexplained_torque = std::nan("");
  // The worst frames by P1 position error (frame, m), for -v.
  std::vector<std::pair<int64_t, double>> worst_frames;
  std::vector<std::string> notes;

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
