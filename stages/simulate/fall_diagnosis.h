// `--contact ground`: why the robot fell, in the stage's own words.
//
// "fell at t = … s" told a user when, not why; finding out took a debug build that printed the balance
// controller's state (session notes of 2026-11-27/28). Every fall of the shared CMU takes traced that way
// was one of a few stories: the capture point ran off the balance plan while the zero-moment point it
// needed lay outside the standing soles (clamped on their edge), and either no foot was stepping to
// catch it (the source kept both feet planted: CMU 60_10) or the step it needed was past the landing
// shift's cap (CMU 03_04, 09_12); or the controller planned yaw moments no sole could give and the body
// turned off the reference's heading (CMU 07_12). So the simulation keeps, per recorded frame, what
// tells those stories apart (BalanceSample), and a fall's message ends with a summary of the run in which
// balance was lost: numbers, not a verdict, so that a user can judge a take we never saw. Session 33 added
// the plan's own zero-moment point: on the four CMU walks that fall it lay outside the standing soles in
// 89-100 % of that run (14-63 % of the frames of the 17 that stay up; 0 % for a standing robot shoved).
#pragma once

#include <string>
#include <vector>

namespace syn {

// The balance controller's view of one recorded frame (ground mode with balance).
struct BalanceSample {
  double time = 0;             // s
  bool balancing = false;      // some sole was on the floor (the centre-of-mass level was set)
  double capture_error = 0;    // m: the capture point's distance from the balance plan's
  double zmp_shortfall = 0;    // m: how far outside the standing soles the zero-moment point it needed lay
  bool standing_both = false;  // both feet standing (planted in the source and on the floor)
  bool stepping = false;       // a foot was swinging toward a touchdown of the source's
  double landing_needed = 0;   // m: the largest landing shift a swinging foot needed (uncapped; 0 if none)
  double unexplained_yaw = 0;  // N·m: the yaw moment the controller planned that no sole force gave
  // N·m: the same for the tilting moment (about the horizontal axes through the centre of mass). The 17 CMU
  // walks that stay up leave 10-50 N·m of it out (median over the run); CMU 07_12, which tips forward, 92 N·m
  // over its first 0.7 s (session 35; syn-simulate --moment-weight trades it against the force).
  double unexplained_tilt = 0;
  double heading_error = 0;    // deg: the pelvis's heading off the reference's
  // deg: the reference's own heading (the summary unwraps it). Three of the four CMU walks
  // that fall are the shared walks that turn most (235-892 deg per take; the 17 that stay up 8-51 deg),
  // and lost the plan as a turn began (03_04), during one (09_12) or after a half turn (03_03).
  double reference_heading = 0;
  // m: how far outside the standing soles the balance plan's own zero-moment point lay. The plan keeps it
  // inside the feet where the source has them; outside the soles as they stand, the feet are elsewhere
  // (landed off their plan, turned, or touching on an edge), and the plan asks for what no feedback can
  // give: the capture point runs off it at e^(ωt).
  double plan_shortfall = 0;
  int support_points = 0;      // the standing soles' points on the floor (1 or 2: a corner or an edge)
  // m: at the frame a swinging foot landed (the source planted it again), how far its link stood from where
  // the stepping last aimed it (the reference's landing plus the landing shift); negative where no foot
  // landed. CMU 07_12's second step landed 0.20 m short of its aim: its heel touched 86 ms before the
  // source's touchdown, and friction held it while the aim ran on (session 37).
  double landing_miss = -1;
};

// Whether the zero-moment point the feedback wanted lay outside the standing soles, clamped onto their
// edge (more than 5 mm out: not rounding). Never on a frame with no sole on the floor (its shortfall is 0).
[[nodiscard]] bool ZmpClamped(const BalanceSample& sample);
// The same for the balance plan's own zero-moment point.
[[nodiscard]] bool PlanOffTheSoles(const BalanceSample& sample);

// The summary appended to a fall's message. It finds when the capture point left the balance plan for
// good (the last frame it was within 5 cm of it) and when it was past a step's reach (`step_cap`, m, the
// landing shift's cap), and reports over that run: in what share of the frames the zero-moment point it
// needed lay outside the standing soles, and the plan's own; the share the soles stood on an edge or a
// corner; the largest landing shift the steps under way needed, the share of it both feet stayed planted
// with no step under way, the tilting moment no sole gave (largest and median), the largest yaw moment no
// sole gave and the largest heading error; and how far the reference itself turned over the run and over
// the second before it, and how far the feet that landed from that second to the end of the run stood
// from where the stepping aimed them. Empty when there are no samples.
[[nodiscard]] std::string DescribeFall(const std::vector<BalanceSample>& samples, double step_cap);

}  // namespace syn
