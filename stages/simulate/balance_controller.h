// `--contact ground`: the centre of mass moved only by forces the feet can push.
//
// The paper's controller plans generalized forces for every velocity, its driven base's six included.
// On the ground those six must come from the soles, whose forces are unilateral, inside friction cones,
// and whose centre of pressure stays under the feet: a zero-moment point (ZMP) inside the support
// polygon. The paper's PD gains (kp 350) answer a 2 cm sideways error of the pelvis with 7 m/s², on a
// 35 kg G1 a moment of 170 N·m about feet that can push about ±10 N·m: every small error became a
// demand no contact met, the base "followed physics" and the robot tipped.
//
// So, as in momentum-based balance control (Lee & Goswami 2012; Koolen et al. 2016), a level ranks above
// the paper's tasks in ground mode: the base's translational rows of the equations of motion,
// A_b u̇ = F* − (b + g)_b, i.e. the centre of mass accelerates by F*/m − g, and F* is a force the soles
// can push along a ZMP inside them:
//   - horizontally m c̈*, from capture-point feedback on the balance plan (balanced_reference.h;
//     Englsberger's divergent component of motion): ω = 1/√η, ξ = c + ċ/ω,
//     p* = p_plan + (1 + k/ω)(ξ − ξ_plan) clamped into the standing soles' polygon,
//     c̈* = c̈_plan + ω² ((c − c_plan) − (p* − p_plan)), scaled into the friction cone;
//   - vertically m (g + z̈*), z̈* a PD on the plan's centre-of-mass height, kept in [0.2, 3] m g.
// The standing soles: those of feet planted in the source, and of a touching foot the source lifts while
// the capture point is still outside the planted feet's soles (a walk's trailing foot at heel-off, whose
// toe still carries the robot). The angular momentum is left to the tasks: a level that also fixed its
// rate (damped toward the plan's, clipped to the support) fought the arms, a standing G1's wrists ended
// 31° off, and the walks fell no later.
// The base task's horizontal target is rewritten to the measured centre of mass plus the reference's
// offset of the base from it. The controller solves only that task's orientation rows in ground mode
// (ControllerTasks, simulation.h: the level moves the base); the target is what the pelvis's position
// error is measured against.
// Where no sole touches (a jump, a fall, a brisk walk's flight), the level is cleared and the body moves
// ballistically; the task targets stay where the stepping put them (its landing shifts, the swing's lift and
// the plan's offset, as last planned).
//
// Stepping (Pratt's capture point; Englsberger's DCM step adjustment): through a single support the sole
// is all the zero-moment point has, and G1's is 5 cm wide. A capture-point error of 2 cm at the start of
// a 0.5 s stance grows to 15 cm (e^{ωT} ≈ 7) once the zero-moment point sits on the sole's edge. So each
// swinging foot lands where the plan would have it relative to the capture point: its target moves by the
// capture-point error predicted at its touchdown (the source's next planted frame) under the feedback
// above with the zero-moment point clamped into the present support, ė = ω (e − Δp(e)) (an error the
// ankles can return predicts no shift, one past the sole's edge runs away), capped at `max_step_shift`
// and faded in over the swing (smoothstep); when it lands, the whole plan (centre of mass, zero-moment point and every task)
// walks on shifted by that landing shift. Without it no CMU walk stayed up. The swinging foot is also
// carried `swing_lift` higher at mid-swing, clear of the floor it would otherwise scuff, where the reference
// has it in the air (not where the labels lift a foot that pivots on the floor).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "common/model.h"
#include "common/robot_map.h"
#include "stages/simulate/balanced_reference.h"
#include "stages/simulate/fall_diagnosis.h"
#include "stages/simulate/operational_space_controller.h"
#include "stages/simulate/task_references.h"

namespace syn {

struct BalanceControllerOptions {
  double capture_gain = 3.5;    // k, 1/s: the capture point's error decays as e^(−kt) while p* is unclamped
  // 1/s²: centre-of-mass height. The plan's height is the reference's: 2 / 4 cm lower (bent knees, as robot
  // walking controllers keep them) gave 14.50 / 11.25 walks up over 8 runs, against 17.00 (session 48).
  double kp = 350.0;
  double kv = 25.0;             // 1/s: its rate
  double friction = 0.8;        // μ of the planned forces (the contact-force split's)
  double touch_height = 0.002;  // m: a sole point this close to the floor supports (the planned forces')
  // m: the largest landing shift of a stepping foot (0: no stepping). Walks up of the 21 CMU walks onto G1
  // over this cap and capture_gain, with the planned forces on sole points within 2 cm and the torques
  // that keep the held feet (simulation.cpp, contact_consistent_torques.h), 2026-11-28:
  //   gain 3: caps 0.25, 0.28, 0.3, 0.32: 12, 12, 12, 12;  gain 3.5: caps 0.22, 0.28, 0.3, 0.32: 13, 13, 14, 11;
  //   gain 4: caps 0.2, 0.25, 0.3: 11, 8, 12;  gain 4.5, cap 0.28: 11;  gain 5, cap 0.25: 14.
  // 3.5 1/s and 0.3 m sit in the 11-14 region; (4, 0.25), the defaults before, is its low point.
  // Session 48, 8 rounding-level runs of the present controller (the same 8 at the defaults: 17.00): caps
  // 0.4 / 0.5 m: 17.25 / 17.12, the long takes falling no later. 0.4 over three 32-run ensembles, each
  // with its own offsets: 17.22 / 17.31 / 17.12 against 17.12 / 16.72 / 16.91 here, falls per 100 steps
  // 2.79 against 3.04 pooled, most of it 08_07's exaggerated strides (up in 21-27 of 32 against 16-21);
  // not adopted: the tests' own draw then kept 15 walks up, and the brisk walk with its moments favoured
  // (TheBriskWalkStaysUpWithItsMomentsFavoured) touched down at 3.4 kN, 10 body weights. Nor did landing
  // early help: a foot whose shift would pass the cap brought down within 0.1-0.2 s where the capture point
  // would then need it, and held from its touch: 15.88-16.75.
  double max_step_shift = 0.3;
  // m: the height added to a swinging foot's target, lift·sin(π s) at the fraction s of its airborne stretch
  // (balanced_reference.h: the plan does not count the foot as support; no lift where it does, a foot the
  // labels lift but that pivots or slides on the floor). A 1.3 m robot retargeted from a human swings its soles 5-22 mm over the floor;
  // with a few cm of tracking error the heel touches early and friction holds it while the target (and
  // its landing shift) run on: CMU 07_12's second step landed 25 cm short of its target and the robot
  // fell. Walks up over the 8 settings above (mean): lift 0 / 0.02 / 0.03 / 0.04 / 0.05 m: 11.9 / 13.1 /
  // 13.4 / 13.5 / 13.4; a flat-topped profile (1 − (2s − 1)⁴) at 0.03 / 0.04 m: 11.9 / 12.4. (Those runs
  // let 05_01 and 08_07 start past their ankles' limits, plan_start.h; started inside them, 13.0 at 0.04.)
  // Session 50: the lift spanned the labelled swing (lift-off to touchdown) until then, and held CMU 03_03's
  // right foot 4-7 cm up through the 0.47 s it pivots on the floor labelled lifted, while the plan stood on
  // it. Spanning the airborne stretch instead, 32 rounding-level runs keep 17.62 walks up against 17.12,
  // falls per 100 steps 2.57 against 2.88 (03_01, 07_12 and 08_07 up more often; the long takes no later).
  // Also tried then, on 8 runs against 17.62: the landing shift predicted to the airborne stretch's end,
  // 17.62; frozen once the foot is down before its label (faded in by then), 16.38; such a foot counted
  // standing, 17.50; the plan's zero-moment point carried with the standing feet to where they stand, 17.25.
  double swing_lift = 0.04;
};

// What the level decided at one control step (ground frame; zero where no sole touched): for
// `--control-trace` (control_trace.h).
struct BalanceCommand {
  Eigen::Vector2d com = Eigen::Vector2d::Zero(), capture_error = Eigen::Vector2d::Zero();
  Eigen::Vector2d plan_zmp = Eigen::Vector2d::Zero(), wanted_zmp = Eigen::Vector2d::Zero(), commanded_zmp = Eigen::Vector2d::Zero();
  Eigen::Vector3d force = Eigen::Vector3d::Zero();  // the ground force the level asks for, N
};

class BalanceController {
 public:
  BalanceController(const Model& model, const RobotMap& map, const BalanceShift& plan,
                    const std::vector<ControlledTask>& tasks, const BalanceControllerOptions& options);

  // For the state the workspace holds (setQ, setU done) at `fraction` of the way from `frame` to the
  // next, with `planted` [feet] the source's contact flags: sets the controller's centre-of-mass level and
  // rewrites the base task's horizontal reference.
  void apply(Workspace& workspace, int64_t frame, double fraction, const int64_t* planted,
             std::vector<TaskReference>& references, OperationalSpaceController& controller);

  // After apply: what it saw (the balance fields of a BalanceSample; time and the rest are the caller's).
  const BalanceSample& state() const { return state_; }
  const BalanceCommand& command() const { return command_; }

 private:
  const BalanceShift& plan_;
  BalanceControllerOptions options_;
  double mass_, gravity_;
  int base_task_ = -1;
  int base_link_ = -1;
  std::vector<int> translation_velocities_;  // the unactuated velocities that translate the base (the level's rows)
  std::vector<int> foot_links_;
  // Stepping: per foot its task (-1: none), whether the source planted it at the last call, when its
  // swing began and the landing shift planned for it; and the shift of the whole plan so far.
  std::vector<int> foot_tasks_;
  std::vector<bool> was_planted_;
  std::vector<double> swing_start_;
  std::vector<Eigen::Vector2d> landing_shift_;
  // Per foot, where its link stands at this call (x, y), and where the stepping last aimed it in its swing
  // (the target with its landing shift, the plan's offset included); `aimed_` until it lands.
  std::vector<Eigen::Vector2d> foot_position_, landing_aim_;
  std::vector<bool> aimed_;
  Eigen::Vector2d plan_offset_ = Eigen::Vector2d::Zero();
  // Stepping's plan at a call with a sole on the floor: each swinging foot's landing shift, and the plan's
  // offset walked on when a foot lands.
  void step(double now, size_t frame, const int64_t* planted, const Eigen::Vector2d& capture_error,
            const Eigen::Vector2d& zmp_plan, double omega);
  // The task references where that plan puts them: the swinging feet shifted (faded in over the swing) and
  // lifted, every task moved by the plan's offset. Also in a flight, with the shifts last planned.
  void placeReferences(double now, size_t frame, const int64_t* planted, std::vector<TaskReference>& references);
  // When the source next plants `foot` after `frame` (s), if that is after `now`; -1 otherwise (no touchdown
  // left in the take, or it is due): the swing the stepping aims and the lift spans.
  double SwingLanding(size_t foot, size_t frame, double now) const;
  // The capture point's error from the plan `remaining` seconds ahead, under the feedback above with the
  // zero-moment point clamped into the present support (hull_).
  Eigen::Vector2d PredictedCaptureError(const Eigen::Vector2d& capture_error, const Eigen::Vector2d& zmp_plan, double omega,
                                        double remaining) const;
  std::vector<std::vector<Eigen::Vector3d>> sole_points_;    // per foot, in its link frame
  std::vector<std::vector<Eigen::Vector2d>> touching_;       // per foot, its sole points on the floor (x, y)
  std::vector<bool> standing_;
  std::vector<Eigen::Vector2d> support_, hull_;
  BalanceSample state_;
  BalanceCommand command_;
  // m: the largest landing miss since the last call at a frame (-1: none); reportLanding puts it in state_.
  double unreported_miss_ = -1;
  void reportLanding(double fraction);
  Eigen::Matrix<double, 6, Eigen::Dynamic> jacobian_;
  Eigen::VectorXd base_force_;
};

}  // namespace syn
