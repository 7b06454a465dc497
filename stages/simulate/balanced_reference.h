// `--contact ground`: a reference the robot can balance on.
//
// A kinematic retarget copies the human's motion, not the robot's dynamics: on the CMU walks onto G1
// the base wrench it needs lies outside what the soles can push in 76–91 % of frames (median moment
// 41–115 N·m, a zero-moment point about 12 cm outside the feet). Tracked exactly, such a motion falls
// over whatever the controller does. The paper's robot was driven at its base; one on the ground must
// move its centre of mass differently from the human.
//
// Since the whole trial is known offline, the fix is planned before the simulation, as walking pattern
// generators do (Kajita's preview control), with the retargeted motion's own dynamics:
//  1. per frame, the zero-moment point p the reference needs (from its full inverse dynamics: arms,
//     torso rotation and all, the base wrench smoothed over σ = 40 ms: the retargeted accelerations are a
//     spline's through per-frame solutions and spike, 123 m/s² at a CMU walk's pelvis in its first
//     frames) and the support polygon of its stance feet (their sole points near the floor; the feet the
//     source plants or that are low and slow, else the lowest);
//  2. where p lies outside the polygon shrunk by `margin`, the ZMP shift Δp that brings it inside;
//  3. the horizontal centre-of-mass shift Δc that produces Δp. With the centre of mass at height z and
//     vertical ground force F_z, the linear inverted pendulum gives Δp = Δc − η Δc̈, η = m z / F_z. Its
//     bounded solution is Δp convolved with e^(−|t|/√η) / (2√η): the robot leans before it needs to
//     (preview), not after. On the frames: the least-squares Δc of (I − η D²) Δc ≈ Δp, free at both
//     ends (a take that begins mid-stride begins with its centre of mass already on its way: the
//     simulation starts on the plan's first state), a banded system solved in O(frames).
// The controller then tracks every task above the legs (pelvis, torso, head, hands) shifted by
// Δc / α, where α is the fraction of Δc a rigid shift of the body above the hips gives (the legs, whose
// feet stay put, follow half-way): the robot leans, its feet and its posture as the source's; and the
// plan's centre of mass, zero-moment point and momentum are what BalanceController steers to.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>

#include "common/model.h"
#include "common/motion_file.h"
#include "common/robot_map.h"

namespace syn {

using Vector6d = Eigen::Matrix<double, 6, 1>;  // (angular, linear), or (moment, force)

struct BalanceOptions {
  // m: how far each support-polygon vertex moves toward the polygon's centroid before the planned
  // zero-moment point is kept inside it: room for the controller's capture-point feedback, which has
  // nowhere to put its zero-moment point once the plan's sits on a sole's edge (syn-simulate
  // --support-margin; see SimulateOptions for the measurements behind the default).
  double margin = 0.025;
  // s: σ of the Gaussian the reference's base wrench is smoothed with before its zero-moment point is
  // taken (a step lasts about 0.5 s).
  double smoothing = 0.04;
  // deg: where the reference's base turns more than this within kTurnWindow either side of a frame, the
  // support polygon is built from the standing soles' centre lines instead of their whole width (see the
  // .cpp; syn-simulate --centre-line-turn). A value above any turn keeps the whole width everywhere.
  double centre_line_turn = 30.0;
};

struct BalanceShift {
  // Per frame, the horizontal shift of the tasks above the legs (x, y in ground, m) and its first two
  // time derivatives.
  std::vector<Eigen::Vector2d> position, velocity, acceleration;
  // Per frame, the centre of mass the plan gives (the reference's plus the shift's share α): its
  // horizontal position, velocity and acceleration; the zero-moment point it plans (inside `support`);
  // η = m z / F_z; and the support polygon (shrunk by the margin; empty when no foot is near the floor).
  std::vector<Eigen::Vector2d> com, com_velocity, com_acceleration, zmp;
  std::vector<double> eta;
  // The reference's centre-of-mass height, its rate and acceleration (m, m/s, m/s²), and its angular
  // momentum about the centre of mass and that momentum's rate (the smoothed moment), ground frame.
  std::vector<double> com_height, com_height_velocity, com_height_acceleration;
  std::vector<Eigen::Vector3d> angular_momentum, angular_momentum_rate;
  std::vector<std::vector<Eigen::Vector2d>> support;
  // The frame times, and per map foot and frame the first frame at or after it where the source plants
  // that foot after a swing (a touchdown; -1 if none follows): when a swinging foot lands.
  std::vector<double> time;
  std::vector<std::vector<int64_t>> next_touchdown;
  // Per map foot and frame span (frame t to t + 1): when the span's airborne stretch began and ends (s), the
  // run of spans in which the foot is not among the plan's supports at both ends; -1 where it supports
  // throughout the span. A foot the source lifts but keeps on the floor (a pivot) is no swing here.
  std::vector<std::vector<double>> airborne_start, airborne_end;
  // Every link on a foot's chain up to (not including) the base: tasks there are not shifted.
  std::vector<bool> leg_link;
  // Diagnostics: frames whose reference ZMP lay outside the shrunk support, the largest ZMP correction
  // and the largest shift (m).
  int64_t corrected_frames = 0;
  double largest_zmp_correction = 0;
  double largest_shift = 0;
};

// Counter-clockwise convex hull of `points` (sorted in place); 1 or 2 points for a degenerate set.
void ConvexHull(std::vector<Eigen::Vector2d>& points, std::vector<Eigen::Vector2d>& hull);

// The point of the convex polygon `hull` (counter-clockwise; 1 or 2 points for a point or a segment)
// nearest to p: p itself when inside.
[[nodiscard]] Eigen::Vector2d ClosestInPolygon(const Eigen::Vector2d& p, const std::vector<Eigen::Vector2d>& hull);

// The joints from the link `foot_link` up its chain to the root or the floating base (fixed joints
// included, the added free joint not), foot first.
[[nodiscard]] std::vector<const ModelJoint*> FootChain(const Model& model, const std::string& foot_link);

// The shift for `motion` (q, u, udot; contact flags if it has them) on `model` with `map`'s feet.
[[nodiscard]] BalanceShift PlanBalanceShift(const MotionData& motion, const Model& model, const RobotMap& map,
                                            const BalanceOptions& options);

}  // namespace syn
