// syn-retarget IN.markers.h5 -o OUT.motion.h5 --model ROBOT.urdf --robot-map MAP.toml --markerset SET.toml
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <functional>
#include <iostream>
#include <numeric>
#include <optional>
#include <string>
#include <vector>

#include "common/cli.h"
#include "common/intermediate_file.h"
#include "common/motion_file.h"
#include "stages/retarget/retarget.h"

namespace {

// -v: where a landmark is furthest from its target, by position (part 0, m) or angle (part 1, rad): the
// `count` worst frames at least `apart` seconds from each other (neighbouring frames of one bad stretch would
// fill the list), each with its landmark, so a user knows which frames to look at first.
void PrintWorstFrames(const syn::MotionData& motion, int part, size_t count, double apart) {
  const size_t landmarks = motion.landmark_names.size(), frames = static_cast<size_t>(motion.frames());
  if (landmarks == 0 || motion.landmark_error.size() != frames * landmarks * 2) return;
  std::vector<double> worst(frames, -1.0);
  std::vector<size_t> which(frames, 0);
  for (size_t t = 0; t < frames; ++t) {
    for (size_t l = 0; l < landmarks; ++l) {
      const double error = motion.landmark_error[(t * landmarks + l) * 2 + static_cast<size_t>(part)];
      if (std::isfinite(error) && error > worst[t]) worst[t] = error, which[t] = l;
    }
  }
  std::vector<size_t> order(frames);
  std::iota(order.begin(), order.end(), 0);
  std::stable_sort(order.begin(), order.end(), [&](size_t a, size_t b) { return worst[a] > worst[b]; });
  std::vector<size_t> chosen;
  for (const size_t t : order) {
    if (chosen.size() == count || worst[t] < 0) break;
    const bool near = std::any_of(chosen.begin(), chosen.end(), [&](size_t c) {
      return std::abs(motion.time_s[c] - motion.time_s[t]) < apart;
    });
    if (near) continue;
    chosen.push_back(t);
    std::cerr << "syn-retarget: worst " << (part == 0 ? "position" : "angle") << " error #" << chosen.size() << ": frame "
              << t << " (t = " << motion.time_s[t] << " s), " << motion.landmark_names[which[t]] << " "
              << (part == 0 ? worst[t] * 1000 : worst[t] * 180 / M_PI) << (part == 0 ? " mm" : " deg") << "\n";
  }
}

// The parser of an option that is a number or `map`, the robot map's value (`target` left unset); the
// number's range is RetargetOptions::IsValid's to check.
std::function<void(const std::string&)> MapOrNumber(const std::string& flag, const std::string& expected,
                                                    std::optional<double>& target) {
  return [flag, expected, &target](const std::string& text) {
    if (text == "map") {
      target.reset();
      return;
    }
    char* end = nullptr;
    const double value = std::strtod(text.c_str(), &end);
    if (end == text.c_str() || *end != '\0') throw CLI::ValidationError(flag, "must be map or " + expected + ", not '" + text + "'");
    target = value;
  };
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Retarget a capture onto a humanoid: landmark poses relative to the reference stance, scaled by "
               "robot/subject height and turned to face +X, tracked by per-frame inverse kinematics (Ceres, joint "
               "limits as bounds, priorities as weights: paper Table I); velocities and accelerations by central "
               "differences; torques by Simbody inverse dynamics with gravity and no contact (a free base's six "
               "entries are the residual wrench).",
               "syn-retarget"};
  syn::CommonFlags common;
  syn::AddCommonFlags(app, common);
  syn::RetargetOptions options;
  std::string input;
  app.add_option("INPUT", input, "Markers file from syn-ingest")->required();
  app.add_option("--model", options.model, "Robot URDF")->required();
  app.add_option("--robot-map", options.robot_map, "Robot map (manifests/robots/NAME.toml)")->required();
  app.add_option("--markerset", options.markerset, "Marker set (manifests/markersets/NAME.toml)")->required();
  app.add_option_function<std::string>(
         "--floating-base",
         [&](const std::string& text) {
           if (!syn::ParseFloatingBaseChoice(text, &options.floating_base)) {
             throw CLI::ValidationError("--floating-base", "must be map, auto, free or fixed, not '" + text + "'");
           }
         },
         "map (as the robot map says) | auto | free | fixed")
      ->default_str("map");
  app.add_option("--reference-time", options.reference_time,
                 "Time (s) of the reference stance; negative: the capture's calibration frame when the robot map's stance is "
                 "that pose (stance_is_calibration_pose), else the first frame where every tracked landmark is present")
      ->capture_default_str();
  app.add_option_function<std::string>(
         "--scale",
         [&](const std::string& text) {
           char* end = nullptr;
           const double value = std::strtod(text.c_str(), &end);
           if (text == "auto") options.scale = 0.0;
           else if (!text.empty() && *end == '\0' && value > 0) options.scale = value;
           else throw CLI::ValidationError("--scale", "must be auto or a positive number, not '" + text + "'");
         },
         "Robot/subject height ratio for landmark displacements, or auto (measured: head to feet, in the capture's "
         "standing calibration frame when it has one, else at the reference frame)")
      ->default_str("auto");
  app.add_option_function<std::string>("--velocity-limit-scale", MapOrNumber("--velocity-limit-scale", "a number >= 0", options.velocity_limit_scale),
                                       "Bound each frame's joint step by this multiple of the URDF velocity limit (0: "
                                       "unbounded). map: the robot map's velocity_limit_scale (1 unless it says)")
      ->default_str("map");
  app.add_option("--smoothing", options.smoothing,
                 "Trajectory refinement: weight of accelerations against tracking (1: 10 rad/s^2 costs like 1 mm); "
                 "0 = per-frame IK only")
      ->capture_default_str();
  app.add_option("--posture-scale", options.posture_scale,
                 "Multiply the robot map's posture weight (toward the reference stance); about 10 for joint-centre "
                 "data without segment orientations, whose arms otherwise drift onto their limits")
      ->capture_default_str();
  app.add_option("--ik-function-tolerance", options.ik_function_tolerance,
                 "Per-frame IK: stop when an iteration changes the cost by less than this fraction")
      ->capture_default_str();
  app.add_option("--contact-height", options.contact.height,
                 "Contact detection: a source foot is planted below this height (m, capture "
                 "units) above the capture's ground (a low percentile of the foot landmarks' heights); 0.05 = GMD's "
                 "foot-skating contact height")
      ->capture_default_str();
  app.add_option("--contact-speed", options.contact.speed,
                 "... and slower than this horizontal speed (m/s); default 0.5/1.5, so a contact ends by --contact-release "
                 "at GMD's sliding speed 0.5 m/s")
      ->capture_default_str();
  app.add_option("--contact-release", options.contact.release,
                 "Hysteresis: a contact ends only above height and speed times this (>= 1)")
      ->capture_default_str();
  app.add_option("--contact-uneven-ground", options.contact.uneven_ground,
                 "Contact detection: a slow foot whose other foot swings above it is planted whatever its height above the "
                 "capture's ground (steps, blocks, ramps; a walk has no flight phase)")
      ->capture_default_str();
  app.add_option("--contact-min-duration", options.contact.min_duration,
                 "Contact phases shorter than this (s) are dropped (0.1 s: the shortest human stance, sprinting)")
      ->capture_default_str();
  app.add_option("--level-floor", options.floor.enabled,
                 "Turn the take so its floor is level: a plane fitted to the standing foot landmarks (mocap floors are often "
                 "tilted about 1°: CMU's walks rise up to 21 mm per metre); not when the fit is no floor (more than "
                 "--level-floor-max-tilt, or 15 mm residual: uneven terrain)")
      ->capture_default_str();
  app.add_option_function<double>(
         "--level-floor-max-tilt", [&](double degrees) { options.floor.max_tilt = degrees * M_PI / 180; },
         "The largest floor tilt (degrees) --level-floor corrects")
      ->default_str("2.86");
  app.add_option_function<double>(
         "--level-floor-min-tilt", [&](double degrees) { options.floor.min_tilt = degrees * M_PI / 180; },
         "The smallest floor tilt (degrees) --level-floor corrects (a level floor's fit is that noisy)")
      ->default_str("0.286");
  app.add_option("--flatten-terrain", options.flatten_terrain,
                 "On a take whose standing feet fit no floor (uneven terrain, steps), lower each raised plant onto the "
                 "robot's flat floor and the body with it, so the robot walks the terrain's steps on level ground")
      ->capture_default_str();
  app.add_option("--hold-foot-yaw", options.hold_foot_yaw,
                 "Hold each foot's orientation target within the turn about the pelvis its leg's vertical-axis joints "
                 "can make (a source foot that swivels further is not followed by bending the leg onto its limits)")
      ->capture_default_str();
  app.add_option("--enforce-contacts", options.enforce_contacts,
                 "Make the source's contacts exact, above every task: planted soles flat on z = 0 and still, no sole "
                 "point below the floor, the base lowered where a planted leg cannot reach (false: measured only)")
      ->capture_default_str();
  app.add_option("--contact-blend", options.enforcement.blend,
                 "Outside a contact phase the planted correction's height and tilt fade over this time (s)")
      ->capture_default_str();
  app.add_option("--contact-blend-horizontal", options.enforcement.horizontal_blend,
                 "... and its horizontal shift and turn over this time (s): a foot leaving or meeting its plant "
                 "returns to the source's path no faster than the source's own foot moves there")
      ->capture_default_str();
  app.add_option("--stance-knee", options.enforcement.stance_knee,
                 "A corrected leg keeps its knee bent at least this much (rad); where the foot is then out of reach, "
                 "the base is lowered")
      ->capture_default_str();
  app.add_option("--max-lowering", options.enforcement.max_lowering,
                 "The base is lowered by at most this fraction of the leg")
      ->capture_default_str();
  app.add_option("--lowering-smoothing", options.enforcement.lowering_smoothing,
                 "Half-width (s) of the smoothing of the base lowering (never below what reach needs)")
      ->capture_default_str();
  app.add_option_function<std::string>(
         "--proportions",
         [&](const std::string& text) {
           if (text != "map" && text != "height" && text != "chains") {
             throw CLI::ValidationError("--proportions", "must be map, height or chains, not '" + text + "'");
           }
           if (text == "map") options.proportions_per_chain.reset();
           else options.proportions_per_chain = text == "chains";
         },
         "How landmark displacements are scaled when --scale is auto: height (one ratio, the head's height above the "
         "feet), chains (legs by hip-knee-ankle length, arms by shoulder-elbow-hand length) or map (the robot map's "
         "proportions, height unless it says)")
      ->default_str("map");
  app.add_option("--heading-from-pelvis", options.heading_from_pelvis,
                 "Take the heading from the pelvis frame averaged over the capture (a mid-stride reference frame turns "
                 "the feet's left-right vector, and planted feet cannot lie flat; false: the feet's and elbows' left-right "
                 "vector at the reference frame)")
      ->capture_default_str();
  app.add_option("--neutral-reference", options.neutral_reference,
                 "Measure the feet from their median offset to the pelvis over the take "
                 "(a walk's first frame is mid-stride; false: from the reference frame, as a calibration frame or "
                 "--reference-time always is)")
      ->capture_default_str();
  app.add_option("--move-base-for-plants", options.enforcement.move_base_for_plants,
                 "Where a planted foot is out of its leg's reach from the tracked pelvis (a leg joint on its limit), "
                 "turn and shift the pelvis by the least amount that lets the planted legs reach (the upper body moves "
                 "with it; a free base only). false: the foot falls short and slides")
      ->capture_default_str();
  app.add_option_function<std::string>(
         "--base-smoothing", MapOrNumber("--base-smoothing", "a time in s", options.base_smoothing),
         "Half-width (s) of the smoothing of the pelvis moves --move-base-for-plants makes. map: the robot map's "
         "base_smoothing (0.1 unless it says)")
      ->default_str("map");
  app.add_option_function<std::string>(
         "--max-roll", MapOrNumber("--max-roll", "an angle in rad", options.max_roll),
         "Planted feet pitch with the source about their heel or toe edge (heel strike, toe-off) by at most this "
         "angle (rad) instead of lying flat; the sole centre moves with the roll. map: the robot map's max_roll "
         "(0, flat, unless it says)")
      ->default_str("map");
  app.add_option("--contacts-above-speed", options.enforcement.contacts_above_speed,
                 "A planted foot's leg may exceed its URDF velocity limits to keep the foot still (position limits "
                 "kept; a prototype: the legs jump where a contact phase begins). false: every leg joint within its "
                 "limit, the foot sliding where the leg cannot keep up. The summary counts the joint-frames over them")
      ->capture_default_str();
  app.add_option("--friction", options.contact_forces.friction,
                 "Friction coefficient of the sole contact forces that explain the base's residual wrench (the friction "
                 "cone's slope; the motion's contact_force and unexplained_wrench)")
      ->capture_default_str();
  app.add_option("--max-bridge", options.max_bridge,
                 "Longest stretch (s) with no landmark at all that is bridged by interpolation; longer ones fail")
      ->capture_default_str();
  return syn::RunTool(app, argc, argv, [&] {
        std::string problem;
        if (!options.HasValidValues(&problem)) throw syn::UsageError(problem);
        return options.ToJson();
      }, [&] {
    syn::RequireValid(options);
    if (common.verbose) std::cerr << "syn-retarget parameters: " << syn::CanonicalJson(options.ToJson()) << "\n";
    syn::RetargetSummary summary;
    const syn::RetargetInputs inputs = syn::LoadRetargetInputs(input, options);
    syn::Workspace workspace(inputs.model);
    const syn::MotionData motion = syn::Retarget(inputs, workspace, options, &summary);
    for (const std::string& note : summary.notes) std::cerr << "syn-retarget: note: " << note << "\n";

    syn::Provenance provenance;
    provenance.schema = syn::kMotionSchema;
    provenance.schema_version = syn::kMotionSchemaVersion;
    provenance.producer = std::string("syn-retarget ") + syn::kVersion;
    provenance.parameters = options.ToJson();
    provenance.inputs = nlohmann::json::array({syn::DescribeInput(input), syn::DescribeInput(options.model),
                                               syn::DescribeInput(options.robot_map), syn::DescribeInput(options.markerset)});
    syn::IntermediateWriter writer(common.output, provenance);
    syn::WriteMotionData(writer, motion);
    if (!summary.foot_sides.empty()) {
      // The quality figures a user filters trials by (syn-release's quality table reads them).
      writer.writeAttribute("", "floor_tilt_deg", summary.floor_tilt_rad * 180 / M_PI);
      writer.writeAttribute("", "floor_levelled", static_cast<int64_t>(summary.floor_levelled ? 1 : 0));
      // The turn the take was given (the capture's coordinates to the targets'), for tools that draw the
      // capture beside the robot.
      writer.writeAttribute("", "floor_rotation_w", summary.floor_rotation.w());
      writer.writeAttribute("", "floor_rotation_x", summary.floor_rotation.x());
      writer.writeAttribute("", "floor_rotation_y", summary.floor_rotation.y());
      writer.writeAttribute("", "floor_rotation_z", summary.floor_rotation.z());
      writer.writeAttribute("", "stance_drift_median_mm", summary.median_drift * 1000);
      writer.writeAttribute("", "stance_drift_p95_mm", summary.p95_drift * 1000);
      writer.writeAttribute("", "deepest_penetration_mm", summary.deepest_penetration * 1000);
      writer.writeAttribute("", "penetration_frames_ratio", summary.penetrating_fraction);
      writer.writeAttribute("", "foot_skating", summary.foot_skating);
      writer.writeAttribute("", "source_foot_skating", summary.source_foot_skating);
    }
    if (summary.contacts_enforced) {
      // What ranking planted feet above the motors' speed cost (contact_enforcement.h).
      writer.writeAttribute("", "overspeed_joint_frames", summary.enforcement.overspeed_joint_frames);
      writer.writeAttribute("", "worst_speed_ratio", summary.enforcement.worst_speed_ratio);
      writer.writeAttribute("", "worst_speed_joint", summary.enforcement.worst_speed_joint);
      writer.writeAttribute("", "worst_speed_time_s", summary.enforcement.worst_speed_time);
      // Stances held with a leg joint on its limit (contact_enforcement.h).
      writer.writeAttribute("", "planted_foot_frames", summary.enforcement.planted_foot_frames);
      writer.writeAttribute("", "limited_stance_frames", summary.enforcement.limited_stance_frames);
      writer.writeAttribute("", "most_limited_joint", summary.enforcement.most_limited_joint);
    }
    writer.commit();
    std::cerr << "syn-retarget: " << input << " -> " << common.output << ": " << summary.BriefReport() << "\n";
    if (common.verbose) {
      for (size_t i = 0; i < summary.contact_phases.size() && i < summary.phase_drift.size(); ++i) {
        const syn::ContactPhase& phase = summary.contact_phases[i];
        std::cerr << "syn-retarget: contact " << summary.foot_sides[static_cast<size_t>(phase.foot)] << " frames "
                  << phase.begin << "-" << phase.end - 1 << ": stance drift " << summary.phase_drift[i] * 1000 << " mm\n";
      }
      if (summary.deepest_frame >= 0) {
        std::cerr << "syn-retarget: deepest sole point " << summary.deepest_penetration * 1000 << " mm below the floor at frame "
                  << summary.deepest_frame << "\n";
      }
      PrintWorstFrames(motion, 0, 5, 0.25);
      PrintWorstFrames(motion, 1, 5, 0.25);
    }
  });
}
