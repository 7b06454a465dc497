// `--contact ground`: the feet the robot stands on, held where they touched down.
//
// A foot the source plants whose sole touches the floor (its lowest sole point within `touch_height`)
// is a contact, not a task: its sole centre is anchored on the floor where it touched down, with the
// heading it had, and flat. StanceFeet gives the controller those constraints as acceleration rows,
// J_f u̇ = a*_f − J̇_f u with a*_f a critically damped PD back to the anchor (stiffer than the tasks'),
// which the operational-space controller ranks above the centre of mass and every task. The planned
// motion then keeps the standing feet still, so the sole forces the contact split gives are the floor's
// own reaction and the legs move the body over feet that stay put. Left to the pose tasks of priority 1
// instead (shared with the pelvis and the hands, and dropped where they conflict), a stance foot rolled
// onto its heel edge in CMU 02_01's first step, and the zero-moment point the balance plan needed
// 15 cm ahead of that edge could not be reached.
// Ranked first is not held exactly: the hierarchy keeps a row only with 70 % of its mobility independent
// of the rows it took before (ControllerOptions::hierarchy), and in single stance that leaves 2-4 of a
// held foot's 6 rows (CMU 02_01 and 07_06 onto G1, 333 sampled steps: the yaw in 331, the pitch in 91);
// the contact-consistent torques then weigh the six back in (contact_consistent_torques.h). Held exactly
// (cutoff 10⁻⁶ on this level) 3 of the 21 CMU walks stayed up instead of 15; position and yaw alone,
// 13 exactly and 14.6 at 0.7 (mean of 16 rounding-level runs, against 15.4): session 43.
//
// Heel-off: syn-retarget rolls a planted foot about its toe near the end of its phase, as the source's
// heel rises (up to 0.2 rad, robot map `max_roll`). Held flat to the end of the phase, the G1's foot
// had to roll first once the source lifted it, and left the floor 0.11-0.13 s after the source's label
// ended (median, on swings of about 0.4 s). So while the reference foot's sole is tilted toe-down by more
// than `heel_off_tilt`, a held foot keeps only its toe (the front sole points' centroid, anchored where
// it was when heel-off began) and its heading: four rows, the foot free to roll with its task. 16
// rounding-level runs of the 21 CMU walks onto G1 (session 44): 16.81 walks up on average against 16.06
// held flat; CMU 07_12, the brisk walk, up in 13 of the 16 (in none held flat), 08_07 in 9 instead of 15.
#pragma once

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "common/model.h"
#include "common/robot_map.h"

namespace syn {

struct StanceFeetOptions {
  double touch_height = 0.002;  // m: a sole point this close to the floor touches it
  double stiffness = 900.0;     // 1/s²: the hold's PD (damping 2√k: critical)
  double off_flat = 3.0 * M_PI / 180.0;  // rad: a held sole tilted more is counted (tiltedFootSteps)
  double heel_off_tilt = 0.03;  // rad: a reference sole tilted toe-down more than this is at heel-off
};

// How far a foot whose link has `rotation` is tilted from level (rad): the angle of its sole's normal
// (the link's z axis; the robot maps' sole points share their z) from the vertical.
[[nodiscard]] inline double SoleTilt(const Eigen::Matrix3d& rotation) { return std::acos(std::clamp(rotation(2, 2), -1.0, 1.0)); }

// Whether such a foot is at heel-off: tilted more than `tilt` (rad), toe (+x) down.
[[nodiscard]] inline bool HeelOff(const Eigen::Matrix3d& rotation, double tilt) {
  return rotation(2, 0) < 0 && SoleTilt(rotation) > tilt;
}

// The heading of a rotation: its x axis's direction about the vertical (rad). What StanceFeet holds a foot
// at, and what its landings are measured with on both sides.
[[nodiscard]] inline double Heading(const Eigen::Matrix3d& rotation) { return std::atan2(rotation(1, 0), rotation(0, 0)); }

class StanceFeet {
 public:
  StanceFeet(const Model& model, const std::vector<RobotFoot>& feet, const StanceFeetOptions& options);

  // For the state the workspace holds (setQ, setU done) and the source's contact flags `planted` [feet]:
  // which feet are held, and their rows. Returns how many feet are held. `reference_heading` [feet], if
  // given: the heading (rad) the reference motion gives each planted foot at the source's touchdown that
  // began its phase (NaN for none), against which a phase's first hold is measured (phaseDrift).
  // `heel_off` [feet], if given: whether the reference foot is at heel-off (HeelOff), held then by its toe.
  int update(Workspace& workspace, const int64_t* planted, const double* reference_heading = nullptr,
             const char* heel_off = nullptr);

  // After update: per held foot, 6 rows (angular then linear, at the sole centre) or at heel-off 4 (the
  // heading, then the toe's position), and their wanted accelerations minus the velocity terms.
  const Eigen::MatrixXd& jacobian() const { return jacobian_; }
  const Eigen::VectorXd& acceleration() const { return acceleration_; }
  bool held(size_t foot) const { return stance_[foot].held; }
  bool heldByTheToe(size_t foot) const { return stance_[foot].heel_off; }
  // Over every update so far: the held foot-steps, and those whose sole was more than `off_flat` (rad)
  // from flat, on an edge or a corner (a 3° roll lifts a G1 sole's far edge 2.6 mm, past the 2 mm the
  // contact calls touching).
  int64_t heldFootSteps() const { return held_foot_steps_; }
  int64_t tiltedFootSteps() const { return tilted_foot_steps_; }

  // How far held feet moved over each contact phase of the source (a foot planted from one lift-off to
  // the next), against the pose its sole had when the phase's first hold began: the largest turn about
  // the vertical (rad) and the largest horizontal move of the sole centre (m). A hold that lapses for a
  // moment (the sole a few mm up) re-anchors where the foot then is, so a foot can creep hold by hold;
  // this measure spans the whole phase and sees that. Phases still open count as they stand. Medians are
  // nearest-rank (common/percentile.h), as syn-retarget reports its stance drift.
  struct PhaseDrift {
    int64_t phases = 0;
    double median_turn = 0, p95_turn = 0, largest_turn = 0;  // rad
    double median_move = 0, p95_move = 0, largest_move = 0;  // m
    // The phases whose first hold had a reference heading, and how far (rad, either way) the sole's heading
    // was from it then: where the foot landed turned. The balance plan moves a landing (capture-point
    // stepping) but never turns it, so this is the swing's and the touchdown's error.
    int64_t landings = 0;
    double median_landing_turn = 0, p95_landing_turn = 0, largest_landing_turn = 0;  // rad
  };
  PhaseDrift phaseDrift() const;
  // Room for `phases` finished phases, so that update() does not allocate.
  void reservePhases(size_t phases);

 private:
  struct Stance {
    bool held = false;
    bool heel_off = false;                                 // held, by the toe and heading only
    Eigen::Vector3d toe_anchor = Eigen::Vector3d::Zero();  // the toe's, on the floor, from heel-off's start
    Eigen::Vector3d anchor = Eigen::Vector3d::Zero();  // the sole centre's, on the floor (ground frame)
    double yaw = 0.0;                                  // the heading it touched down with
    // The source's contact phase: whether one under way has been held (so the source planted the foot at
    // the last update), the sole centre and heading at its first hold, and the largest turn and move since.
    bool phase_held = false;
    Eigen::Vector2d phase_start = Eigen::Vector2d::Zero();
    double phase_yaw = 0.0, phase_turn = 0.0, phase_move = 0.0;
  };
  StanceFeetOptions options_;
  std::vector<int> foot_links_;
  std::vector<std::vector<Eigen::Vector3d>> sole_points_;  // per foot, in its link frame
  std::vector<Eigen::Vector3d> sole_centre_;               // per foot, in its link frame
  std::vector<Eigen::Vector3d> toe_;                       // per foot, its front sole points' centroid (link frame)
  std::vector<Stance> stance_;
  std::vector<Eigen::Isometry3d> pose_;                    // per foot, its link's pose at the last update
  Eigen::Matrix<double, 6, Eigen::Dynamic> foot_jacobian_;
  Eigen::MatrixXd jacobian_;
  Eigen::VectorXd acceleration_;
  int64_t held_foot_steps_ = 0, tilted_foot_steps_ = 0;
  std::vector<double> phase_turns_, phase_moves_;  // per finished phase that was held
  std::vector<double> landing_turns_;              // per phase whose first hold had a reference heading
};

}  // namespace syn
