// Contacts as constraints on the retargeted motion (issue 17): after the IK and
// the trajectory refinement have tracked the Table I tasks, the source's contact
// phases are made exact, above every task.
//
// 0. Free poses. Outside contact the feet follow the source's positions: each
//    foot's target is its landmark target's position (the capture scaled to
//    the robot), moved down so that the source's planted frames sit on the floor
//    (the median lowest sole point over them at z = 0), with the tracked pose's
//    orientation, and the tracked pose where the landmark is missing. The IK's
//    own foot positions are a compromise with targets the legs cannot reach
//    together (a pelvis above straight legs), which kept swing feet 1-3 cm off
//    the floor; its orientations are kept because the source's foot orientation
//    is noisy (a CMU dance's foot roll jitters by 0.5 rad between frames, which
//    an exact leg solve reproduces and the IK's weighting smooths away). Where
//    the tracked orientation hangs an unplanted sole lower than the source's
//    own (its lowest point, with the source's orientation), the foot rises to
//    the source's clearance, so a swing foot does not skim the floor.
// 1. Planted poses. During each contact phase the foot's sole lies flat on
//    z = 0 and does not move: its yaw is the circular mean of the foot's yaw over
//    the phase and its sole centre the mean of the sole centre's horizontal
//    position (of the free poses), so the plant sits where the source put the
//    foot and the correction is as small as it can be. With `max_roll` > 0,
//    within 0.1 s of the phase's ends (heel strike, toe-off), the plant rolls
//    about its heel or toe edge, which stays put on the floor, by the source
//    foot's pitch from its median over the phase, at most max_roll (the robot
//    map's max_roll unless --max-roll says).
// 2. Blending. Outside a phase the correction (planted pose ⊖ tracked pose, as a
//    translation and a rotation vector) fades with a cubic ease over `blend`
//    seconds (its horizontal shift and turn about z over `horizontal_blend`),
//    or over the gap to the next phase of that foot when it is shorter,
//    so the foot's path stays continuous at touchdown and lift-off. Any frame's
//    foot target whose lowest sole point would be below z = 0 is raised onto it.
// 3. Reach. Each corrected leg is first solved with its knee (branch joints,
//    branch_joints.h) kept at least `stance_knee` bent. Where the foot falls
//    short, the distance the leg did reach from its hip is the radius the target
//    must come within, and the base is lowered by the least amount that brings
//    it there, never by more than `max_lowering` × the leg, smoothed over
//    `lowering_smoothing` seconds so that the lowering is never less than needed
//    (a running maximum, then two box filters of half that width). The upper
//    body moves down with the base.
// 3b. Pelvis. Where a planted foot is still out of its leg's reach from the
//    lowered pelvis (a leg joint on its limit: a dancer turning on one foot
//    further than the robot's hip allows), the pelvis turns and shifts by the
//    least amount with which every planted leg reaches its plant, smoothed in
//    time; the upper body moves with it. A free base, or a virtual base chain
//    of x, y, z slides and x, y, z turns (HRP-4C's), moves so (base_mover.h).
// 3c. Swing clearance. The free poses' clearance (step 0) assumed the legs
//    pitch the swing feet as asked; where an ankle limit pitches a foot further
//    on the lowered, moved robot (its toes hanging under the source's), the legs
//    are solved for every unplanted frame first, and the foot rises by what its
//    sole lacks of its target's height (at most the source's clearance),
//    smoothed, growing from the foot's plants at most 20 m/s² up to 1 m/s.
// 4. Legs. Each frame whose foot targets differ from where the lowered robot
//    puts its feet is solved exactly for those feet by the leg chains
//    (leg_chain.h), every other joint unchanged, each leg joint within its
//    velocity limit of the previous frame, except, with `contacts_above_speed`,
//    a planted foot's leg: the contact then ranks above the motors' speed. The
//    joint-frames over their limit are reported either way. A leg carried
//    over straight that ends off its target is solved again from a bent knee.
//    Where a phase's first frame leaves the foot off its plant (legs too slow
//    for the swing: HRP-4C), the phase is planted where the foot touched down
//    (laid flat), the move easing out after the phase. Where a planted leg,
//    within its speed limits, still cannot hold its plant, the pelvis moves
//    this frame too (Levenberg-Marquardt, at most 0.01 rad and 5 mm a frame
//    from the last frame's move, returning to the tracking at that rate when
//    nothing needs holding). Where the limits still leave a sole
//    in the floor (an ankle that cannot pitch the foot flat, a knee that
//    cannot bend as fast as the body drops), the foot stands on its lowest
//    point instead: its target rises by the depth, and if the leg cannot lift
//    it there, the base rises too. Where the leg's limits leave a
//    sole point below the floor (the ankle cannot bend as far as the body passes
//    over the planted foot), the target rolls about the toe or heel edge the
//    foot pitches onto, and the leg is solved again. Before those floor rounds, a planted foot left above
//    the floor (a leg at full stretch, or too slow to bring the foot down at touchdown) brings the base
//    down onto it, where no other foot pays for it (slides, sinks, or leaves its target).
//
// How much a trial needed each step is reported, so a user sees where the
// tracked motion and the contacts disagreed.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <Eigen/Geometry>

#include "common/model.h"
#include "common/robot_map.h"
#include "stages/retarget/contact_detection.h"

namespace syn {

struct ContactEnforcementOptions {
  double blend = 0.1;               // s: a planted correction's height and tilt fade over this outside its phase
  double horizontal_blend = 0.3;    // s: ... and its horizontal shift and turn over this (step 2)
  double stance_knee = 0.15;        // rad a corrected leg's knee keeps (human stance knees bend 5-20°)
  double max_lowering = 0.2;        // of the straight leg
  double lowering_smoothing = 0.2;  // s: 0.1 s bobbed the pelvis every step (bundled walk on the human model 4.0 W/kg; 3.7 at 0.2)
  // rad: planted feet pitch with the source about their heel or toe edge by at most this much near their
  // phase's ends (step 1; 0: flat).
  double max_roll = 0.0;
  // Where a planted foot is out of its leg's reach from the tracked pelvis (a leg joint on its limit), the
  // pelvis moves, by the least rotation and translation that lets every planted leg reach its plant
  // (step 3b), smoothed over `base_smoothing` seconds as the lowering is.
  bool move_base_for_plants = true;
  double base_smoothing = 0.1;      // s
  // Leg joints move at most this fraction of their URDF velocity limit per frame (the stage's
  // --velocity-limit-scale; 0: unbounded): a foot the leg cannot follow that fast falls short (reported)
  // instead of the leg jumping to another configuration (a knee 0.96 rad in one frame of CMU 05_11).
  double velocity_limit_scale = 1.0;
  // A planted foot's leg is solved without that bound (its position limits kept): the contact ranks above
  // the motors' speed (issue 17), and what it costs is reported (ContactEnforcementReport::overspeed_*).
  // HRP-4C's URDF limits (knee 3.07, hip pitch 2.74, ankle pitch 2.09 rad/s) bound 30-85 % of a CMU walk's
  // stance frames, whose knees move at 5-7 rad/s, and its planted feet slid instead: on the 32 CMU walks and
  // dances the trials' stance drift medians went from 6.7-128 mm (median 34.8) to 0-41 (3.8), 23 trials
  // within 10 mm median and 25 mm p95 (was 1). Not yet the default: the legs then jump where a phase begins
  // (the swing leg, still bounded, lags its blend-in, and the first planted frame snaps onto the plant —
  // 02_01's left knee 0.92 -> 0.36 rad in one frame), worst steps 5-97 times the limit, 29-3040 leg
  // joint-frames over it per trial; G1, whose limits rarely bind, 0-8 (07_01, 08_01, 94_07 change).
  bool contacts_above_speed = false;

  bool IsValid(std::string* error) const;
};

struct ContactEnforcementReport {
  double max_lowering = 0.0;            // m the base was lowered at most
  int64_t lowered_frames = 0;           // frames lowered by more than 1 mm
  // Frames where the legs left a planted foot's sole centre more than 5 mm (horizontally) off its plant.
  int64_t unreachable_frames = 0;
  int64_t capped_lowering_frames = 0;   // foot-frames whose plant needed the base lowered past its cap

  int64_t solved_frames = 0;            // frames whose legs were re-solved
  double worst_position_error = 0.0;    // m: the largest foot error the leg solve left (a joint limit)
  double worst_angle_error = 0.0;       // rad
  int64_t worst_frame = -1;
  double mean_iterations = 0.0;         // leg-solver iterations per solved frame
  int64_t rolled_foot_frames = 0;       // foot-frames rolled about a sole edge (a joint limit pitched the foot)
  int64_t lifted_frames = 0;            // frames with a foot lifted onto its lowest sole point (its leg at a limit)
  int64_t clearance_frames = 0;         // frames with a swing foot raised for the clearance its leg's pitch took (step 3c)
  int64_t moved_plants = 0;             // contact phases planted where the foot touched down, off the plan
  int64_t speed_base_moved_frames = 0;  // frames whose pelvis moved so that planted legs hold within their speed
  int64_t raised_frames = 0;            // of those, frames whose base rose too (the leg could not lift the foot)
  int64_t lowered_onto_plant_frames = 0;  // frames whose base came down onto a planted foot its leg left in the air
  double max_lowering_onto_plant = 0.0;   // m: the largest such step down
  int64_t base_moved_frames = 0;        // frames whose pelvis moved so that a planted leg reaches its plant
  double max_base_turn = 0.0;           // rad: the largest such rotation
  double max_base_shift = 0.0;          // m: the largest such translation
  // The legs' joints against their URDF velocity limits over the result (each frame's step from the one
  // before): joint-frames over the limit, the largest speed / limit, and where (coordinate, frame).
  int64_t overspeed_joint_frames = 0;
  double worst_speed_ratio = 0.0;
  std::string worst_speed_joint;
  int64_t worst_speed_frame = -1;
  double worst_speed_time = 0.0;        // s, of worst_speed_frame
  // Planted foot-frames (the source's contacts, per foot) over the result, and those whose leg holds a joint
  // within kStanceLimitBand of a position limit (the model's: the URDF's, narrowed by the map's
  // [joint_ranges]): a stance the robot keeps with no room to move further that way, where the capture asked
  // for more than the leg has; and the leg joint most often so. Onto G1, CMU's three turning walks (03_03,
  // 03_04, 09_12) hold a stance ankle on its ±15° roll limit in 18-23 % of their planted foot-frames, the 18
  // straight ones in none (08_07 a hip roll in 2 %).
  int64_t planted_foot_frames = 0;
  int64_t limited_stance_frames = 0;
  std::string most_limited_joint;
  int64_t most_limited_joint_frames = 0;
};

// rad (or m): a leg joint this close to a position limit counts as on it (ContactEnforcementReport).
inline constexpr double kStanceLimitBand = 0.01;

// source_feet[f][t]: foot f's landmark target (NaN translation: missing; NaN in the rotation's first entry:
// position only); empty: the tracked poses are the free poses. q: [T, nq] row-major, in place. `vertical_coordinate`: the coordinate that moves the robot straight up
// (a free base's z or a virtual prismatic joint), -1 when there is none (no lowering then).
void EnforceContacts(const Model& model, Workspace& workspace, const std::vector<RobotFoot>& feet,
                     const FootContacts& contacts, const std::vector<std::vector<Eigen::Isometry3d>>& source_feet,
                     int64_t vertical_coordinate, const std::vector<double>& time_s,
                     const std::string& map_file, const ContactEnforcementOptions& options, std::vector<double>& q,
                     ContactEnforcementReport* report);

}  // namespace syn
