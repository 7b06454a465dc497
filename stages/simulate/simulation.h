// syn-simulate's library: the paper's dynamic mapping. The retargeted motion's tasks are tracked by the
// operational-space controller on the robot simulated in Simbody at the control rate; the motion file it
// returns has q, u, udot from the simulation, tau = the commanded (saturated) torques and the tasks'
// tracking errors, at the input's frame times.
//
// Time stepping: each input frame interval is cut into ceil(interval × rate) equal steps (so a 120 Hz
// capture at 1 kHz takes 9 steps of 0.93 ms): every frame time is hit exactly, the step never exceeds
// 1/rate, and the run is deterministic. The controller runs once per step and holds its torques over it.
#pragma once

#include <array>
#include <memory>
#include <string>
#include <utility>

#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/model.h"
#include "common/motion_file.h"
#include "common/robot_map.h"
#include "stages/simulate/balanced_reference.h"
#include "stages/simulate/control_trace.h"
#include "stages/simulate/contact_consistent_torques.h"
#include "stages/simulate/fixed_step_integrator.h"
#include "stages/simulate/operational_space_controller.h"
#include "stages/simulate/task_references.h"

namespace syn {

// none: the paper's setting, a driven floating base and no ground; ground: compliant sole contact with
// the plane z = 0, the base unactuated and the controller's forces made contact-consistent.
enum class ContactMode { kNone, kGround };
[[nodiscard]] std::string_view ContactModeName(ContactMode mode);

struct SimulateOptions {
  double rate = 1000.0;  // Hz, control and integration rate (paper: a 1 kHz real-time controller)
  ControllerOptions controller;  // kp 350, kv 25: the paper's code
  ContactMode contact = ContactMode::kNone;
  TargetSource targets = TargetSource::kKinematic;
  // Semi-implicit Euler: one dynamics evaluation per step, what keeps the stage ≥ 10× real time; RK4 for
  // accuracy studies (4 evaluations).
  Integrator integrator = Integrator::kSemiImplicitEuler;
  // Ground mode: lean the tasks above the legs so the reference's zero-moment point stays inside the
  // feet (BalanceShift). Off is for diagnosis: the source's motion as retargeted.
  bool balance = true;
  // 1/s: how fast the capture point returns to the plan's (BalanceController).
  double balance_gain = 3.5;
  // m: the largest shift of a stepping foot's landing (BalanceController; 0: no stepping).
  double step_adjustment = 0.3;
  // m: how much higher than the source a swinging foot is carried at mid-swing (BalanceController; 0: as
  // the source).
  double swing_lift = 0.04;
  // m: how far inside the feet the balance plan keeps its zero-moment point (BalanceOptions::margin: each
  // support-polygon vertex moved this far toward the centroid; on a G1 sole, 17 × 5-6 cm, 0.025 takes
  // 2.4 cm off each end and 0.8 cm off each side). At 0.01 a single support's planned zero-moment point
  // often lay on the sole's edge, and a capture-point error toward that side had no zero-moment point
  // left to return it: it grew e^(ωt) until a step, capped, could not catch it (CMU 03_04 drifted
  // 15-25 cm sideways in each 0.7 s stance). CMU walks up of 21 onto G1 over the 8 settings of
  // balance_controller.h (mean; the defaults' count in brackets): margin 0.005: (13); 0.01: 14.88 (14);
  // 0.015: (14); 0.02: 15.25 (15); 0.025: 16.25 (17); 0.03: 16.12 (15); 0.04: 16.50 (16); 0.05: 15.75 (16).
  double support_margin = BalanceOptions{}.margin;
  // Ground mode, deg: where the reference's base turns more than this within half a second either side,
  // the balance plan's support polygon is the standing soles' centre lines (BalanceOptions). See
  // balanced_reference.cpp for the measurements; a value above any turn (1e6) keeps the soles' width.
  double centre_line_turn = BalanceOptions{}.centre_line_turn;
  // Ground mode: how much the planned sole forces favour the base wrench's moments over its force where the
  // soles cannot give both (ContactConsistentOptions::moment_weight; 1: N·m against N one to one).
  double moment_weight = ContactConsistentOptions{}.moment_weight;
  // Ground mode: each swinging foot's heading as a level above the centre of mass's and the tasks'
  // (OperationalSpaceController::setSwingingFeet). Over 32 rounding-level runs of the 21 CMU walks onto
  // G1 (session 47), the landings' heading error from the reference's (each walk that stayed up: its p95)
  // 15.2° → 10.7° median, the worst 141° → 57°; the walks that stay up 16.78 → 16.84 (standard errors
  // 0.15, 0.18). Off is for diagnosis.
  bool swing_heading = true;
  // Ground mode, with swing_heading: over this last fraction of a swing (the source's lift-off to its
  // touchdown) the swinging foot's horizontal position joins its heading's level (0: left to its task). 16
  // rounding-level runs of the 21 CMU walks onto G1 (session 47, heading level on; walks up, falls per 100
  // steps), with the height too: 0: 17.06, 3.14; the whole swing: 15.88, 4.04 (12_02 fell in its first step
  // in 12 runs: yaw moments no sole gave); 0.5: 17.06, 2.97; 0.3: 17.25, 2.77 (09_12 falls after 10-20 of
  // its 29 steps instead of 5-10, 03_03 after 5-26 of 52 instead of 4-14); 0.2: 17.25, 2.91. The height
  // left to the task, 0.3: 17.19, 2.88, and touchdowns as soft as without (walks' peak vertical force p90
  // 4.8 body weights against 5.3 with the height). Session 48: a landing foot counted as planted as soon as
  // two of its sole points touch (the source plants feet up to 0.17 s after the reference's heel is down,
  // and a foot turned 22° on the floor in between, CMU 03_04): 17.38 over 32 runs, but 16.72 and 16.88 over
  // two other 32-run ensembles where the defaults gave 16.72 and 16.91.
  double swing_landing = 0.3;

  bool IsValid(std::string* error) const;
  nlohmann::json ToJson() const;
};

struct SimulateSummary {
  std::string message = "Simulate was not called.";
  int64_t frames = -1;
  int64_t steps = -1;
  int64_t saturated_steps = -1;    // steps where at least one joint hit its effort limit
  int64_t saturated_entries = -1;  // joint-steps at the limit
  int64_t limited_steps = -1;      // control evaluations where a joint-limit wall was active
  double joint_rms_deg = -1;       // RMS over frames and joints of q_sim − q_kinematic (deg)
  double joint_max_deg = -1;       // the largest |q_sim − q_kinematic| (deg)
  double p1_position_rms_m = -1;   // priority-1 tasks' position error to the references tracked (m)
  double p1_angle_rms_deg = -1;    // ... and angle error (deg)
  // Ground mode only (-1 otherwise): the deepest sole point below the floor over the run (mm), the
  // lowest pelvis height as a fraction of the reference's at the same time, the RMS over frames of the
  // base wrench no admissible sole force explained (N, N·m), and the largest vertical ground force (N).
  double deepest_penetration_mm = -1;
  double lowest_pelvis_ratio = -1;
  double unexplained_force_rms_n = -1;
  double unexplained_torque_rms_nm = -1;
  double peak_vertical_force_n = -1;
  // Ground mode: joint-steps where a joint pressed a mechanical stop (joint_stops.h), and the farthest any
  // joint went past its URDF limit (deg).
  int64_t stopped_joint_steps = -1;
  double worst_limit_excess_deg = -1;
  // Ground mode: the steps solved again because sole points would have pulled (ground_contact.h).
  int64_t released_contact_steps = -1;
  // Ground mode: the control steps × feet a planted foot was held on the floor (stance_feet.h), and those
  // with its sole more than 3° off flat (standing on an edge or a corner).
  int64_t held_foot_steps = -1;
  int64_t tilted_foot_steps = -1;
  // Ground mode: over the source's contact phases whose foot was held, how far the held sole turned
  // (deg) and its centre moved (mm) from where the phase's first hold found it: median, p95, largest
  // (StanceFeet::PhaseDrift; syn-retarget reports the like for the kinematic motion, its stance drift).
  int64_t held_phases = -1;
  double held_turn_median_deg = -1, held_turn_p95_deg = -1, held_turn_max_deg = -1;
  double held_move_median_mm = -1, held_move_p95_mm = -1, held_move_max_mm = -1;
  // Ground mode: over the held phases whose source touchdown the reference gives a heading, how far (deg,
  // either way) the sole's heading at the phase's first hold was from the reference foot's at that
  // touchdown: median, p95, largest (StanceFeet::PhaseDrift). The plan moves landings, never turns them.
  int64_t landings = -1;
  // Ground mode: the take's steps, the source's touchdowns (what a fall's message counts them against).
  int64_t source_steps = -1;
  double landing_turn_median_deg = -1, landing_turn_p95_deg = -1, landing_turn_max_deg = -1;
  // Ground mode with stepping: over the landings of swings the stepping aimed (BalanceSample::landing_miss),
  // how far (mm) the foot's link stood from its aim at the source's touchdown: median, p95, largest.
  int64_t aimed_landings = -1;
  double landing_miss_median_mm = -1, landing_miss_p95_mm = -1, landing_miss_max_mm = -1;
  // Ground mode with balance: the frames whose reference zero-moment point the plan moved into the feet,
  // the largest such move and the largest shift of the body above the legs (m).
  int64_t balance_corrected_frames = -1;
  double balance_largest_zmp_correction_m = -1;
  double balance_largest_shift_m = -1;
  // Ground mode with balance: the recorded frames with a sole on the floor, and those where the
  // zero-moment point the capture-point feedback wanted lay more than 5 mm outside the standing soles
  // (clamped onto their edge: the feedback short of authority; fall_diagnosis.h).
  int64_t balancing_frames = -1;
  int64_t clamped_frames = -1;
  // ... and those where the balance plan's own zero-moment point lay outside the standing soles (the feet
  // not where the plan had them; fall_diagnosis.h).
  int64_t plan_off_frames = -1;

  // Per controller task (the map's, in its order), over the control steps it was solved in, how often the
  // hierarchy kept each of its rows (OperationalSpaceController::keptTaskRows). In ground mode a foot's
  // task counts only while that foot is not held: held, its rows are the stance level's and the task's
  // own are dropped as dependent on them.
  struct TaskRowsKept {
    std::string task;   // its landmark
    bool foot = false;  // ground mode: a map foot's task, counted while that foot is not held
    unsigned rows = 0;  // its rows (TaskRowBits)
    int64_t steps = 0;
    std::array<int64_t, 6> kept{};
  };
  std::vector<TaskRowsKept> task_rows;

  std::string BriefReport() const;
  std::string FullReport() const;
};

struct SimulationResult {
  MotionData motion;
  SimulateSummary summary;
};

// Ground mode's fall: the stage's error, carrying the frames recorded before it (the input's frames up to
// the last one before the fall), which `--fall-record` writes so that a user can look at how it fell.
class FallError : public DataError {
 public:
  FallError(Location where, const std::string& message, MotionData before_fall)
      : DataError(std::move(where), message), before_fall_(std::make_shared<const MotionData>(std::move(before_fall))) {}
  const MotionData& beforeFall() const { return *before_fall_; }

 private:
  std::shared_ptr<const MotionData> before_fall_;  // shared: an exception is copied
};

// The tasks the operational-space controller solves. In ground mode with balance, BalanceController's
// centre-of-mass level, above every task, sets the base's translational rows of the equations of motion:
// the centre of mass moves by the force the soles push, and the height follows the plan's centre-of-mass
// height. A pose task on the free base (the pelvis) then keeps only its orientation rows: its position
// rows asked again, through a PD of their own, for a translation the level had already decided, and
// competed with the feet, hands and head for priority 1's rows. 32 rounding-level runs of the 21 CMU walks
// onto G1 (`make ground-sweep RUNS=16` twice over, session 44): 15.94 walks up on average against 15.22
// with the position rows (03_01 up in 22 of 32 runs instead of 14, 12_03 in 26 instead of 18; 03_03,
// 03_04, 07_12 and 09_12 fall in every run either way); dropping the height row alone 15.56, the
// horizontal rows alone 15.50 (16 runs). The pelvis's position error is still measured against its
// reference (MeasureErrors, BalanceController). Paper mode, and ground mode without balance, track the
// map's tasks as they are.
[[nodiscard]] std::vector<ControlledTask> ControllerTasks(std::vector<ControlledTask> tasks, const Model& model,
                                                          const SimulateOptions& options);

// Throws DataError (naming `motion_name`, the file it came from) when the motion does not fit the model,
// has no frames or the simulation diverges, and in ground mode FallError when the robot falls ("fell at
// t = … s": the pelvis under 60 % of the reference's height at that time). With `trace`, in ground mode with
// balance, one row per control step up to the end or the fall (control_trace.h).
[[nodiscard]] SimulationResult Simulate(const MotionData& motion, const std::string& motion_name, const Model& model,
                                        const RobotMap& map, const SimulateOptions& options, ControlTrace* trace = nullptr);

}  // namespace syn
