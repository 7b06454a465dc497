#include "stages/simulate/simulation.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <sstream>

#include <Eigen/Cholesky>

#include "common/error.h"
#include "common/motion_integration.h"
#include "common/percentile.h"
#include "stages/simulate/balance_controller.h"
#include "stages/simulate/contact_consistent_torques.h"
#include "stages/simulate/fall_diagnosis.h"
#include "stages/simulate/ground_contact.h"
#include "stages/simulate/joint_stops.h"
#include "stages/simulate/plan_start.h"
#include "stages/simulate/stance_feet.h"

namespace syn {
namespace {

constexpr double kDegreesPerRadian = 180.0 / M_PI;
constexpr double kDivergedVelocity = 1e4;
// Ground mode: the robot has fallen when its pelvis is under this fraction of the reference's height.
constexpr double kFallenPelvisRatio = 0.6;
// Ground mode: sole points this close above the floor touch it (the compliant contact sinks a standing
// G1's soles about 0.8 mm): the balance controller's support, and the feet the stance level holds.
constexpr double kPlannedContactHeight = 0.002;
// Ground mode: sole points this close above the floor may carry the planned contact forces. A held sole
// tilted 3° onto an edge lifts its far side 2.6 mm on a G1 (9 mm along its 17 cm length); planned on the
// touching points alone, the forces' centre of pressure could not move onto the lifted side, the ankle
// never pressed the foot back flat, and the support stayed a line or a point (held soles more than 3° off
// flat in 53-89 % of their steps on the 8 CMU walks up). CMU walks up of 21, mean over eight balance
// settings (gain 3-5 1/s × step cap 0.2-0.3 m), with the torques that kept the joints' planned
// accelerations: 6.0 at 2 mm, 9.8 at 6 mm, 10.4 at 1 cm, 11.8 at 2 cm, 11.9 at 3 cm, 11.5 at 5 cm; but a
// sole pressed flat by forces planned where it did not touch yet slapped the floor with up to 13 kN (38
// body weights). With the torques that keep the held feet's rows (contact_consistent_torques.h), 11.9 at
// 2 cm, the peaks on six walks at most 3.4 kN.
constexpr double kPlannedForceHeight = 0.02;

double AngleBetween(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return 2.0 * std::acos(std::min(1.0, std::abs(a.normalized().dot(b.normalized()))));
}

// Whether the source plants, at frame t, the foot whose contact column is `column` (≥ 0).
bool SourcePlants(const MotionData& input, int column, int64_t t) {
  return input.contact[static_cast<size_t>(t) * input.contact_feet.size() + static_cast<size_t>(column)] != 0;
}

// The source's steps in frames [1, end): its touchdowns, a map foot planted again after a frame it was not
// (`contact_column` as for TouchdownHeadings). How far into a take a fall came: the CMU walks that fall in
// every run are the three long takes (29, 52 and 55 steps; the other 18 have 3-9).
int64_t SourceTouchdowns(const MotionData& input, const std::vector<int>& contact_column, int64_t end) {
  int64_t touchdowns = 0;
  for (const int column : contact_column) {
    if (column < 0) continue;
    for (int64_t t = 1; t < end; ++t) touchdowns += SourcePlants(input, column, t) && !SourcePlants(input, column, t - 1) ? 1 : 0;
  }
  return touchdowns;
}

// Per frame and map foot (`contact_column` as for TouchdownHeadings): how far into its swing the source's
// foot is, (k − lift-off + 1) / (touchdown − lift-off + 1) at frame k of a swing between a lift-off and a
// touchdown of the take (so in (0, 1)); -1 where the foot is planted, or its swing began before the take or
// ends after it.
std::vector<double> SwingProgress(const MotionData& input, const std::vector<int>& contact_column) {
  const size_t feet = contact_column.size();
  std::vector<double> progress(static_cast<size_t>(input.frames()) * feet, -1.0);
  for (size_t f = 0; f < feet; ++f) {
    if (contact_column[f] < 0) continue;
    const auto plants = [&](int64_t t) { return SourcePlants(input, contact_column[f], t); };
    for (int64_t start = 0; start < input.frames();) {
      if (plants(start)) {
        ++start;
        continue;
      }
      int64_t end = start;
      while (end < input.frames() && !plants(end)) ++end;
      if (start > 0 && end < input.frames()) {
        for (int64_t k = start; k < end; ++k) {
          progress[static_cast<size_t>(k) * feet + f] = static_cast<double>(k - start + 1) / static_cast<double>(end - start + 1);
        }
      }
      start = end;
    }
  }
  return progress;
}

// Per frame and map foot (frame-major, as the source's contact flags): NaN where the source does not plant
// the foot (or has no contact column for it, -1 in `contact_column`), else the heading of the reference's
// foot link at the frame that began the planted run.
std::vector<double> TouchdownHeadings(const MotionData& input, const Model& model, const RobotMap& map,
                                      const std::vector<int>& contact_column) {
  const size_t frames = static_cast<size_t>(input.frames()), feet = map.feet.size();
  std::vector<double> heading(frames * feet, std::numeric_limits<double>::quiet_NaN());
  Workspace workspace(model);
  const int nq = model.nq();
  for (size_t f = 0; f < feet; ++f) {
    const int column = contact_column[f];
    if (column < 0) continue;
    const int link = model.findLinkIndex(map.feet[f].link);
    const auto planted = [&](size_t t) { return SourcePlants(input, column, static_cast<int64_t>(t)); };
    double phase_heading = std::numeric_limits<double>::quiet_NaN();
    for (size_t t = 0; t < frames; ++t) {
      if (!planted(t)) continue;
      if (t == 0 || !planted(t - 1)) {
        workspace.setQ(Eigen::Map<const Eigen::VectorXd>(&input.q[t * static_cast<size_t>(nq)], nq));
        phase_heading = Heading(workspace.findLinkPose(link).linear());
      }
      heading[t * feet + f] = phase_heading;
    }
  }
  return heading;
}

// Per frame and map foot (frame-major): whether the reference foot is at heel-off (HeelOff with
// `tilt`), where StanceFeet holds it by its toe.
std::vector<char> ReferenceHeelOff(const MotionData& input, const Model& model, const RobotMap& map, double tilt) {
  const size_t frames = static_cast<size_t>(input.frames()), feet = map.feet.size();
  std::vector<char> heel_off(frames * feet, 0);
  std::vector<int> links;
  for (const RobotFoot& foot : map.feet) links.push_back(model.findLinkIndex(foot.link));
  Workspace workspace(model);
  const int nq = model.nq();
  for (size_t t = 0; t < frames; ++t) {
    workspace.setQ(Eigen::Map<const Eigen::VectorXd>(&input.q[t * static_cast<size_t>(nq)], nq));
    for (size_t f = 0; f < feet; ++f) heel_off[t * feet + f] = HeelOff(workspace.findLinkPose(links[f]).linear(), tilt) ? 1 : 0;
  }
  return heel_off;
}

// The tasks' errors at the current state: to the motion's landmark targets (stored, as syn-retarget
// stores them) and to the references the controller tracks (summarised for priority 1).
void MeasureErrors(Workspace& workspace, const std::vector<ControlledTask>& tasks, const MotionData& input, int64_t t,
                   const std::vector<TaskReference>& references, MotionData& output, double& p1_position_sq,
                   double& p1_angle_sq, int64_t& p1_position_count, int64_t& p1_angle_count) {
  const size_t landmarks = input.landmark_names.size();
  for (size_t i = 0; i < tasks.size(); ++i) {
    const ControlledTask& task = tasks[i];
    const Eigen::Isometry3d pose = workspace.findLinkPose(task.link);
    const Eigen::Quaterniond orientation(pose.linear());
    const bool has_position = task.type != TaskType::kOrientation, has_angle = task.type != TaskType::kPosition;
    if (task.priority == 1) {
      if (has_position) p1_position_sq += (pose.translation() - references[i].position).squaredNorm(), ++p1_position_count;
      if (has_angle) p1_angle_sq += std::pow(AngleBetween(orientation, references[i].orientation), 2), ++p1_angle_count;
    }
    if (task.landmark_index < 0) continue;
    const size_t cell = static_cast<size_t>(t) * landmarks + static_cast<size_t>(task.landmark_index);
    const double* target = &input.landmark_targets[cell * 7];
    if (has_position && std::isfinite(target[0])) {
      output.landmark_error[cell * 2] = (pose.translation() - Eigen::Vector3d(target[0], target[1], target[2])).norm();
    }
    if (has_angle && std::isfinite(target[3])) {
      output.landmark_error[cell * 2 + 1] = AngleBetween(orientation, Eigen::Quaterniond(target[3], target[4], target[5], target[6]));
    }
  }
}

// Ground mode starts with the motion's first frame moved vertically so its lowest sole point is on the
// floor: a take that starts mid-stride may hold both feet a little above it (CMU 02_01: 2 cm), and the
// robot would start by falling, out of the controller's reach, until a sole touched.
void StandOnTheFloor(const Model& model, const RobotMap& map, Workspace& workspace, Eigen::VectorXd& q) {
  workspace.setQ(q);
  double lowest = std::numeric_limits<double>::infinity();
  for (const RobotFoot& foot : map.feet) {
    const Eigen::Isometry3d pose = workspace.findLinkPose(model.findLinkIndex(foot.link));
    for (const std::array<double, 3>& p : foot.sole_points) lowest = std::min(lowest, (pose * Eigen::Vector3d(p[0], p[1], p[2])).z());
  }
  if (std::isfinite(lowest)) q[6] -= lowest;  // a free base's z, after its quaternion
}

}  // namespace

std::string_view ContactModeName(ContactMode mode) { return mode == ContactMode::kGround ? "ground" : "none"; }

bool SimulateOptions::IsValid(std::string* error) const {
  const auto fail = [&](const std::string& message) {
    if (error != nullptr) *error = message;
    return false;
  };
  if (!(rate >= 10.0 && rate <= 1e5)) return fail("--rate must be in [10, 100000] Hz, got " + std::to_string(rate));
  if (!(controller.kp > 0) || !std::isfinite(controller.kp)) return fail("--kp must be > 0, got " + std::to_string(controller.kp));
  if (!(controller.kv >= 0) || !std::isfinite(controller.kv)) return fail("--kv must be >= 0, got " + std::to_string(controller.kv));
  const double cutoff = controller.hierarchy.independence_cutoff;
  if (!(cutoff > 0 && cutoff < 1)) return fail("--independence-cutoff must be in (0, 1), got " + std::to_string(cutoff));
  if (!(controller.limit_frequency > 0 && controller.limit_frequency <= 1e4)) {
    return fail("--limit-frequency must be in (0, 10000] rad/s, got " + std::to_string(controller.limit_frequency));
  }
  const double damping = controller.hierarchy.damping;
  if (!(damping >= 0 && damping < 1)) return fail("--damping must be in [0, 1), got " + std::to_string(damping));
  if (!(balance_gain >= 0 && balance_gain <= 1e3)) return fail("--balance-gain must be in [0, 1000] 1/s, got " + std::to_string(balance_gain));
  if (!(step_adjustment >= 0 && step_adjustment <= 1)) return fail("--step-adjustment must be in [0, 1] m, got " + std::to_string(step_adjustment));
  if (!(swing_lift >= 0 && swing_lift <= 0.2)) return fail("--swing-lift must be in [0, 0.2] m, got " + std::to_string(swing_lift));
  if (!(support_margin >= 0 && support_margin <= 0.1)) {
    return fail("--support-margin must be in [0, 0.1] m, got " + std::to_string(support_margin));
  }
  if (!(centre_line_turn >= 0 && centre_line_turn <= 1e6)) {
    return fail("--centre-line-turn must be in [0, 1e6] deg, got " + std::to_string(centre_line_turn));
  }
  if (!(swing_landing >= 0 && swing_landing <= 1)) return fail("--swing-landing must be in [0, 1], got " + std::to_string(swing_landing));
  if (!(moment_weight > 0 && moment_weight <= 100)) {
    return fail("--moment-weight must be in (0, 100], got " + std::to_string(moment_weight));
  }
  if (contact == ContactMode::kGround && integrator != Integrator::kSemiImplicitEuler) {
    return fail("--contact ground needs --integrator euler (the friction anchors move once per step)");
  }
  return true;
}

nlohmann::json SimulateOptions::ToJson() const {
  return {{"rate", rate},
          {"kp", controller.kp},
          {"kv", controller.kv},
          {"independence_cutoff", controller.hierarchy.independence_cutoff},
          {"damping", controller.hierarchy.damping},
          {"no_effort_limits", !controller.effort_limits},
          {"no_joint_limits", !controller.joint_limits},
          {"limit_frequency", controller.limit_frequency},
          {"contact", std::string(ContactModeName(contact))},
          {"targets", std::string(TargetSourceName(targets))},
          {"integrator", std::string(IntegratorName(integrator))},
          {"no_balance", !balance},
          {"balance_gain", balance_gain}, {"step_adjustment", step_adjustment},
          {"swing_lift", swing_lift}, {"support_margin", support_margin}, {"moment_weight", moment_weight},
          {"centre_line_turn", centre_line_turn},
          {"no_swing_heading", !swing_heading}, {"swing_landing", swing_landing}};
}

std::string SimulateSummary::BriefReport() const {
  std::ostringstream out;
  out.precision(3);
  out << frames << " frames, " << steps << " steps; joint RMS to the kinematic motion " << joint_rms_deg << " deg (max "
      << joint_max_deg << "); priority-1 RMS " << p1_position_rms_m * 1000 << " mm, " << p1_angle_rms_deg
      << " deg; torque limit hit in " << saturated_steps << " steps, a joint-limit wall active in " << limited_steps
      << " steps";
  return out.str();
}

std::string SimulateSummary::FullReport() const {
  std::ostringstream out;
  out.precision(3);
  out << BriefReport() << "\n  saturated joint-steps: " << saturated_entries;
  if (deepest_penetration_mm >= 0) {
    out << "\n  ground: deepest sole point " << deepest_penetration_mm << " mm below the floor, lowest pelvis "
        << lowest_pelvis_ratio * 100 << " % of the reference's height, peak vertical force " << peak_vertical_force_n
        << " N; base wrench no sole force explains (RMS): " << unexplained_force_rms_n << " N, "
        << unexplained_torque_rms_nm << " N·m; joints on their mechanical stops in " << stopped_joint_steps
        << " joint-steps, at most " << worst_limit_excess_deg << " deg past a limit; held soles more than 3 deg off flat in "
        << tilted_foot_steps << " of " << held_foot_steps << " foot-steps; steps solved again without sole points that would pull: "
        << released_contact_steps;
    out << "\n  held feet over the source's " << held_phases << " contact phases, from where each phase's first hold found"
        << " them: turned " << held_turn_median_deg << " deg median, " << held_turn_p95_deg << " p95, " << held_turn_max_deg
        << " at most; sole centre moved " << held_move_median_mm << " mm median, " << held_move_p95_mm << " p95, "
        << held_move_max_mm << " at most";
    out << "\n  landings: the first hold of " << landings << " phases turned " << landing_turn_median_deg
        << " deg median from the reference's heading at the source's touchdown, " << landing_turn_p95_deg << " p95, "
        << landing_turn_max_deg << " at most; the take's " << source_steps << " steps (the source's touchdowns)";
    if (balance_corrected_frames >= 0) {
      out << "\n  balance plan: the reference's zero-moment point moved into the feet in " << balance_corrected_frames
          << " of " << frames << " frames, by up to " << balance_largest_zmp_correction_m * 1000
          << " mm; the body above the legs shifted up to " << balance_largest_shift_m * 1000 << " mm";
      out << "\n  balance: the zero-moment point the capture point needed lay outside the standing soles in "
          << clamped_frames << " of the " << balancing_frames << " frames with a sole on the floor, and the balance plan's own"
          << " (the standing soles not where the plan had the feet) in " << plan_off_frames;
    }
    if (aimed_landings >= 0) {
      out << "\n  landing aims: " << aimed_landings << " feet landed " << landing_miss_median_mm << " mm median from where"
          << " the stepping aimed them at the source's touchdown, " << landing_miss_p95_mm << " p95, " << landing_miss_max_mm
          << " at most";
    }
  }
  if (!task_rows.empty()) {
    // Row names in keptTaskRows's bits: rotations about, then moves along, the ground's axes.
    static constexpr std::array<const char*, 6> kRowNames = {"rx", "ry", "rz", "x", "y", "z"};
    out << "\n  hierarchy: rows kept per control step, mean (the least-kept row, share of steps):";
    const char* separator = " ";
    for (const TaskRowsKept& tally : task_rows) {
      if (tally.steps == 0) continue;
      int64_t kept = 0, least = -1;
      int count = 0, least_row = 0;
      for (int r = 0; r < 6; ++r) {
        if (!((tally.rows >> r) & 1u)) continue;
        ++count, kept += tally.kept[static_cast<size_t>(r)];
        if (least < 0 || tally.kept[static_cast<size_t>(r)] < least) least = tally.kept[static_cast<size_t>(r)], least_row = r;
      }
      out << separator << tally.task << (tally.foot ? " not held " : " ")
          << static_cast<double>(kept) / static_cast<double>(tally.steps) << " of " << count << " ("
          << kRowNames[static_cast<size_t>(least_row)] << " " << 100.0 * static_cast<double>(least) / static_cast<double>(tally.steps)
          << " %)";
      separator = ", ";
    }
  }
  out << "\n  " << message;
  return out.str();
}

std::vector<ControlledTask> ControllerTasks(std::vector<ControlledTask> tasks, const Model& model, const SimulateOptions& options) {
  if (options.contact != ContactMode::kGround || !options.balance) return tasks;
  const int base = model.freeBaseLink();
  for (ControlledTask& task : tasks) {
    if (base >= 0 && task.link == base && task.type == TaskType::kPose) task.type = TaskType::kOrientation;
  }
  return tasks;
}

SimulationResult Simulate(const MotionData& input, const std::string& input_name, const Model& model,
                          const RobotMap& map, const SimulateOptions& options, ControlTrace* trace) {
  std::string problem;
  if (!options.IsValid(&problem)) throw UsageError(problem);
  CheckMotionMatchesModel(input, model);
  if (input.frames() < 1) throw DataError(Location::InFile(input_name), "the motion has no frames");
  for (int64_t t = 1; t < input.frames(); ++t) {
    if (!(input.time_s[static_cast<size_t>(t)] > input.time_s[static_cast<size_t>(t - 1)])) {
      throw DataError(Location::AtFrame(input_name, t), "time does not increase");
    }
  }
  const int nq = model.nq(), nu = model.nu();
  const std::vector<ControlledTask> tasks = BindTasks(map, model, input);
  TaskReferences references(input, model, tasks, options.targets);
  OperationalSpaceController controller(model, ControllerTasks(tasks, model, options), options.controller);
  const bool ground = options.contact == ContactMode::kGround;
  if (ground && !model.hasFreeBase()) {
    throw UsageError("--contact ground needs a free-floating base (the robot stands on its feet)");
  }
  if (ground && map.feet.empty()) {
    throw DataError(Location::InFile(map.file), "--contact ground needs the robot map's [feet] sole points");
  }
  std::optional<GroundContact> ground_contact;
  std::optional<ContactConsistentTorques> distribution;
  std::optional<StanceFeet> stance_feet;
  const StanceFeetOptions stance_options{.touch_height = kPlannedContactHeight};
  std::optional<JointStops> joint_stops;
  // The source's planted flags per map foot (zero where the motion has none).
  std::vector<int> contact_column(map.feet.size(), -1);
  joint_stops.emplace(model, JointStopOptions{});
  if (ground) {
    ground_contact.emplace(model, map.feet, GroundContactOptions{});
    ContactForceOptions planned;
    planned.max_height = kPlannedForceHeight;
    distribution.emplace(model, map.feet, planned, options.controller.effort_limits,
                         ContactConsistentOptions{.moment_weight = options.moment_weight});
    stance_feet.emplace(model, map.feet, stance_options);
    stance_feet->reservePhases(static_cast<size_t>(input.frames()) * map.feet.size());
    for (size_t f = 0; f < map.feet.size(); ++f) {
      for (size_t c = 0; c < input.contact_feet.size(); ++c) {
        if (input.contact_feet[c] == map.feet[f].side) contact_column[f] = static_cast<int>(c);
      }
    }
  }
  // Ground mode: per frame and map foot the source plants it, the heading (rad) the reference motion gives
  // that foot at the touchdown that began the phase (NaN elsewhere): what StanceFeet measures a landing
  // against.
  std::vector<double> touchdown_heading;
  if (ground) touchdown_heading = TouchdownHeadings(input, model, map, contact_column);
  std::vector<char> heel_off;
  if (ground) heel_off = ReferenceHeelOff(input, model, map, stance_options.heel_off_tilt);
  BalanceShift balance;
  std::optional<BalanceController> balance_controller;
  if (ground && options.balance) {
    balance = PlanBalanceShift(input, model, map, BalanceOptions{.margin = options.support_margin, .centre_line_turn = options.centre_line_turn});
    references.shiftAboveLegs(balance, tasks);
    BalanceControllerOptions balance_options;
    balance_options.capture_gain = options.balance_gain;
    balance_options.max_step_shift = options.step_adjustment;
    balance_options.swing_lift = options.swing_lift;
    balance_options.kp = options.controller.kp;
    balance_options.kv = options.controller.kv;
    balance_options.touch_height = kPlannedContactHeight;
    balance_controller.emplace(model, map, balance, tasks, balance_options);
  }
  std::vector<int64_t> planted(map.feet.size(), 0);
  FixedStepIntegrator integrator(model);
  Workspace workspace(model);

  SimulationResult result;
  if (ground && options.balance) {
    result.summary.balance_corrected_frames = balance.corrected_frames;
    result.summary.balance_largest_zmp_correction_m = balance.largest_zmp_correction;
    result.summary.balance_largest_shift_m = balance.largest_shift;
  }
  MotionData& out = result.motion;
  SimulateSummary& summary = result.summary;
  out.time_s = input.time_s;
  out.coordinate_names = input.coordinate_names;
  out.velocity_names = input.velocity_names;
  out.landmark_names = input.landmark_names;
  out.landmark_targets = input.landmark_targets;
  out.landmark_error.assign(input.landmark_error.size(), std::nan(""));
  if (out.landmark_error.size() != static_cast<size_t>(input.frames()) * input.landmark_names.size() * 2) {
    out.landmark_error.assign(static_cast<size_t>(input.frames()) * input.landmark_names.size() * 2, std::nan(""));
  }
  out.model_name = model.name();
  out.model_sha256 = model.sourceSha256();
  out.total_mass = model.totalMass();
  const int64_t frames = input.frames();
  out.q.resize(static_cast<size_t>(frames * nq));
  out.u.resize(static_cast<size_t>(frames * nu));
  out.udot.resize(static_cast<size_t>(frames * nu));
  out.tau.resize(static_cast<size_t>(frames * nu));

  Eigen::VectorXd q = Eigen::Map<const Eigen::VectorXd>(input.q.data(), nq);
  Eigen::VectorXd u = Eigen::Map<const Eigen::VectorXd>(input.u.data(), nu);
  if (ground) StandOnTheFloor(model, map, workspace, q);
  if (ground && options.balance) {
    StartOnThePlan(model, map, balance, workspace, q, u);
    // Its re-solved legs may leave the stance foot above the floor (a near-straight knee cannot reach down
    // where the shifted base asks: CMU 07_12's right sole 13 mm up, and 05_01, 08_01 and 12_03 started with
    // no sole on the floor, the robot falling for its first 40 ms with nothing to steer the centre of mass by).
    StandOnTheFloor(model, map, workspace, q);
  }
  Eigen::VectorXd tau(nu), udot(nu), contact_forces(nu), applied(nu), planned_udot(nu), released_forces(nu), released_udot(nu);
  Eigen::MatrixXd contact_stiffness(nu, nu), contact_damping(nu, nu), implicit_mass(nu, nu);
  Eigen::LDLT<Eigen::MatrixXd> implicit_solver(nu);
  std::vector<TaskReference> task_references;
  PostureReference posture;
  summary.steps = summary.saturated_steps = summary.saturated_entries = summary.limited_steps = 0;
  // The hierarchy's kept rows per task, and which map foot a task moves (-1: none).
  std::vector<int> foot_of_task(controller.tasks().size(), -1);
  for (size_t i = 0; i < controller.tasks().size(); ++i) {
    const ControlledTask& task = controller.tasks()[i];
    SimulateSummary::TaskRowsKept tally;
    tally.task = task.landmark;
    tally.rows = TaskRowBits(task.type);
    for (size_t f = 0; ground && f < map.feet.size(); ++f) {
      if (model.findLinkIndex(map.feet[f].link) == task.link) foot_of_task[i] = static_cast<int>(f);
    }
    tally.foot = foot_of_task[i] >= 0;
    summary.task_rows.push_back(std::move(tally));
  }
  double joint_sq = 0, joint_max = 0, p1_position_sq = 0, p1_angle_sq = 0;
  int64_t joint_count = 0, p1_position_count = 0, p1_angle_count = 0;
  // Ground mode: per map foot its task's index (-1: none), and the swinging feet's tasks per control step.
  std::vector<int> task_of_foot(map.feet.size(), -1);
  for (size_t i = 0; i < foot_of_task.size(); ++i) {
    if (foot_of_task[i] >= 0) task_of_foot[static_cast<size_t>(foot_of_task[i])] = static_cast<int>(i);
  }
  std::vector<OperationalSpaceController::SwingingFoot> swinging_feet;
  swinging_feet.reserve(map.feet.size());
  std::vector<double> swing_progress;
  if (ground) swing_progress = SwingProgress(input, contact_column);
  ControlTraceRow trace_row;
  const auto record_control_step = [&](int64_t frame, double fraction, double dt, const Eigen::VectorXd& velocity,
                                     const Eigen::VectorXd& acceleration, ControlTrace& out) {
    const size_t a = static_cast<size_t>(frame), b = std::min(a + 1, input.time_s.size() - 1);
    trace_row.time = (1 - fraction) * input.time_s[a] + fraction * input.time_s[b];
    trace_row.frame = frame;
    trace_row.balancing = balance_controller->state().balancing;
    trace_row.level = balance_controller->command();
    trace_row.planned_force.setZero();
    for (const Eigen::Vector3d& force : distribution->planned().foot_force) trace_row.planned_force += force;
    trace_row.applied_force.setZero();
    for (const Eigen::Vector3d& force : ground_contact->appliedFootForce(velocity, acceleration, dt)) trace_row.applied_force += force;
    trace_row.unexplained = distribution->planned().unexplained;
    trace_row.landing_needed = balance_controller->state().landing_needed;
    out.add(trace_row);
  };
  if (trace != nullptr) trace->reserve(static_cast<size_t>(std::ceil((input.time_s.back() - input.time_s.front()) * options.rate)) + static_cast<size_t>(input.frames()) + 1);
  const auto control = [&](int64_t frame, double fraction, double dt) {
    workspace.setQ(q);
    workspace.setU(u);
    references.sample(frame, fraction, task_references, posture);
    for (size_t f = 0; f < planted.size(); ++f) {
      const int c = contact_column[f];
      planted[f] = c >= 0 && SourcePlants(input, c, frame) ? 1 : 0;
    }
    if (stance_feet) {
      const size_t cell = static_cast<size_t>(frame) * map.feet.size();
      if (stance_feet->update(workspace, planted.data(), &touchdown_heading[cell], &heel_off[cell]) > 0) {
        controller.setStanceLevel(stance_feet->jacobian(), stance_feet->acceleration());
      } else {
        controller.clearStanceLevel();
      }
    }
    if (balance_controller) balance_controller->apply(workspace, frame, fraction, planted.data(), task_references, controller);
    if (stance_feet && options.swing_heading) {
      // A foot the source lifts and the stance level does not hold; landing over its swing's last part.
      swinging_feet.clear();
      for (size_t f = 0; f < map.feet.size(); ++f) {
        if (planted[f] != 0 || stance_feet->held(f) || task_of_foot[f] < 0) continue;
        const double progress = swing_progress[static_cast<size_t>(frame) * map.feet.size() + f];
        swinging_feet.push_back({static_cast<size_t>(task_of_foot[f]), progress >= 1.0 - options.swing_landing});
      }
      controller.setSwingingFeet(swinging_feet);
    }
    int saturated = controller.calcTorques(workspace, task_references, posture, tau);
    for (size_t i = 0; i < summary.task_rows.size(); ++i) {
      const int foot = foot_of_task[i];
      if (foot >= 0 && stance_feet->held(static_cast<size_t>(foot))) continue;
      const unsigned kept = controller.keptTaskRows(i);
      SimulateSummary::TaskRowsKept& tally = summary.task_rows[i];
      ++tally.steps;
      for (size_t r = 0; r < tally.kept.size(); ++r) tally.kept[r] += (kept >> r) & 1u;
    }
    if (ground) {
      controller.calcAcceleration(tau, planned_udot);
      // The held feet's rows (none when no foot is held).
      saturated += distribution->apply(workspace, controller.massMatrix(), controller.biasForces(), planned_udot, planted.data(),
                                       stance_feet->jacobian(), stance_feet->acceleration(), tau);
      ground_contact->calcForces(workspace, contact_forces, contact_stiffness, contact_damping);
    } else {
      contact_forces.setZero();
      contact_stiffness.setZero();
      contact_damping.setZero();
    }
    // The joints' stops, in both modes: with the driven base of paper mode too, a joint the effort limits let
    // fall behind would otherwise turn on past its limits.
    const int engaged = joint_stops->add(q, u, dt, contact_forces, contact_stiffness, contact_damping);
    summary.stopped_joint_steps += engaged;
    if (!ground && engaged == 0) {
      controller.calcAcceleration(tau, udot);  // free of floor and stops (most paper-mode steps): O(n)
    } else {
      // Linearly implicit in the contact and stop forces: (A + h B + h² K) u̇ = τ + f − b − g − h K u, the step
      // semi-implicit Euler takes with the forces at its end (u + h u̇, q + h (u + h u̇)) to first order.
      const auto solve = [&] {
        applied = tau + contact_forces - controller.biasForces();
        applied.noalias() -= dt * (contact_stiffness * u);
        implicit_mass = controller.massMatrix() + dt * contact_damping + dt * dt * contact_stiffness;
        implicit_solver.compute(implicit_mass);
        udot = implicit_solver.solve(applied);
      };
      solve();
      // Sole points whose tangent would pull over the step: solved again without them, then with the
      // forces they reach at its end (ground_contact.h). Twice at most: the second round only for points the
      // first round's forces turned to pulling.
      for (int round = 0; ground && round < 2 &&
                          ground_contact->releasePullingPoints(u, udot, dt, contact_forces, contact_stiffness, contact_damping) > 0;
           ++round) {
        solve();
        released_forces = ground_contact->releasedForces(u, udot, dt, [&](const Eigen::VectorXd& force, Eigen::VectorXd& response) {
          response = implicit_solver.solve(force);
        });
        released_udot = implicit_solver.solve(released_forces);
        udot += released_udot;
        if (round == 0) ++summary.released_contact_steps;
      }
    }
    if (trace != nullptr && balance_controller) record_control_step(frame, fraction, dt, u, udot, *trace);
    summary.saturated_entries += saturated;
    summary.saturated_steps += saturated > 0 ? 1 : 0;
    summary.limited_steps += controller.activeLimitCount() > 0 ? 1 : 0;
  };
  if (ground) {
    out.contact_feet.clear();
    for (const RobotFoot& foot : map.feet) out.contact_feet.push_back(foot.side);
    out.contact.assign(static_cast<size_t>(frames) * map.feet.size(), 0);
    out.contact_force.assign(static_cast<size_t>(frames) * map.feet.size() * 3, 0.0);
    out.unexplained_wrench.assign(static_cast<size_t>(frames) * 6, 0.0);
    summary.deepest_penetration_mm = 0;
    summary.lowest_pelvis_ratio = std::numeric_limits<double>::infinity();
    summary.peak_vertical_force_n = 0;
  }
  if (ground) summary.source_steps = SourceTouchdowns(input, contact_column, frames);
  summary.stopped_joint_steps = 0;
  summary.released_contact_steps = ground ? 0 : -1;
  summary.worst_limit_excess_deg = 0;
  // Ground mode with balance: per recorded frame, what a fall's message summarises (fall_diagnosis.h).
  std::vector<BalanceSample> balance_samples;
  if (balance_controller) balance_samples.reserve(static_cast<size_t>(frames));
  double unexplained_force_sq = 0, unexplained_torque_sq = 0;
  for (int64_t t = 0; t < frames; ++t) {
    // The interval to the next frame in equal steps of at most 1/rate (the last frame: one nominal step,
    // used only by the ground's implicit contact terms at the recorded state).
    const double interval = t + 1 < frames ? input.time_s[static_cast<size_t>(t + 1)] - input.time_s[static_cast<size_t>(t)]
                                           : 1.0 / options.rate;
    const int64_t steps = std::max<int64_t>(1, static_cast<int64_t>(std::ceil(interval * options.rate - 1e-9)));
    const double dt = interval / static_cast<double>(steps);
    control(t, 0.0, dt);
    // Record the frame: the state, the acceleration and torques the controller commands there.
    std::copy(q.data(), q.data() + nq, out.q.begin() + t * nq);
    std::copy(u.data(), u.data() + nu, out.u.begin() + t * nu);
    std::copy(udot.data(), udot.data() + nu, out.udot.begin() + t * nu);
    std::copy(tau.data(), tau.data() + nu, out.tau.begin() + t * nu);
    MeasureErrors(workspace, tasks, input, t, task_references, out, p1_position_sq, p1_angle_sq, p1_position_count,
                  p1_angle_count);
    if (ground) {
      const size_t feet = map.feet.size();
      const std::vector<Eigen::Vector3d>& applied = ground_contact->appliedFootForce(u, udot, dt);
      for (size_t f = 0; f < feet; ++f) {
        const Eigen::Vector3d& force = applied[f];
        out.contact[static_cast<size_t>(t) * feet + f] = ground_contact->footTouches(f) ? 1 : 0;
        std::copy(force.data(), force.data() + 3, out.contact_force.begin() + static_cast<std::ptrdiff_t>((static_cast<size_t>(t) * feet + f) * 3));
        summary.peak_vertical_force_n = std::max(summary.peak_vertical_force_n, force.z());
      }
      const Eigen::Matrix<double, 6, 1>& unexplained = distribution->planned().unexplained;
      if (balance_controller) {
        BalanceSample sample = balance_controller->state();
        sample.time = input.time_s[static_cast<size_t>(t)];
        sample.unexplained_yaw = unexplained[2];
        sample.unexplained_tilt = unexplained.head<2>().norm();
        const double reference_yaw = BaseYaw(&input.q[static_cast<size_t>(t * nq)]);
        sample.heading_error = std::remainder(BaseYaw(q.data()) - reference_yaw, 2 * M_PI) * kDegreesPerRadian;
        sample.reference_heading = reference_yaw * kDegreesPerRadian;
        balance_samples.push_back(sample);
      }
      std::copy(unexplained.data(), unexplained.data() + 6, out.unexplained_wrench.begin() + t * 6);
      unexplained_torque_sq += unexplained.head<3>().squaredNorm();
      unexplained_force_sq += unexplained.tail<3>().squaredNorm();
    }
    for (const ModelJoint& joint : model.joints()) {
      if (joint.q_index < 0 || joint.type == "free") continue;
      const double error = q[joint.q_index] - input.q[static_cast<size_t>(t * nq + joint.q_index)];
      joint_sq += error * error, ++joint_count;
      joint_max = std::max(joint_max, std::abs(error));
    }
    if (t + 1 == frames) break;
    for (int64_t step = 0; step < steps; ++step) {
      if (step > 0) control(t, static_cast<double>(step) / static_cast<double>(steps), dt);
      integrator.step(workspace, options.integrator, tau, dt, &udot, q, u);
      ++summary.steps;
      // Any velocity above 10⁴ (rad/s or m/s) is a blown-up step, caught before Simbody sees NaN poses.
      if (!q.allFinite() || !u.allFinite() || u.cwiseAbs().maxCoeff() > kDivergedVelocity) {
        throw DataError(Location::AtFrame(input_name, t), "the simulation diverged at t = " + std::to_string(input.time_s[static_cast<size_t>(t)] + (step + 1) * dt) + " s");
      }
      summary.worst_limit_excess_deg = std::max(summary.worst_limit_excess_deg, joint_stops->worstExcess(q) * kDegreesPerRadian);
      if (ground) {
        summary.deepest_penetration_mm = std::max(summary.deepest_penetration_mm, ground_contact->deepestPenetration() * 1000);
        // The base's position is q[4..6] (after its quaternion); the reference's at the frame ahead.
        const double fraction = static_cast<double>(step + 1) / static_cast<double>(steps);
        const double reference = (1 - fraction) * input.q[static_cast<size_t>(t * nq + 6)] + fraction * input.q[static_cast<size_t>((t + 1) * nq + 6)];
        const double ratio = q[6] / reference;
        summary.lowest_pelvis_ratio = std::min(summary.lowest_pelvis_ratio, ratio);
        if (ratio < kFallenPelvisRatio) {
          std::ostringstream why;
          why.precision(3);
          why << "fell at t = " << input.time_s[static_cast<size_t>(t)] + (step + 1) * dt << " s";
          if (summary.source_steps > 0) {
            why << ", after " << SourceTouchdowns(input, contact_column, t + 1) << " of the take's " << summary.source_steps << " steps";
          }
          why << ": the pelvis is " << q[6]
              << " m high, under " << kFallenPelvisRatio * 100 << " % of the reference's " << reference << " m"
              << DescribeFall(balance_samples, options.step_adjustment);
          KeepFirstFrames(out, t + 1);
          throw FallError(Location::InFile(input_name), why.str(), std::move(out));
        }
      }
    }
  }
  summary.frames = frames;
  if (balance_controller) {
    summary.balancing_frames = summary.clamped_frames = summary.plan_off_frames = 0;
    std::vector<double> misses;
    for (const BalanceSample& sample : balance_samples) {
      summary.balancing_frames += sample.balancing ? 1 : 0;
      summary.clamped_frames += ZmpClamped(sample) ? 1 : 0;
      summary.plan_off_frames += PlanOffTheSoles(sample) ? 1 : 0;
      if (sample.landing_miss >= 0) misses.push_back(sample.landing_miss * 1000);
    }
    if (options.step_adjustment > 0) {
      summary.aimed_landings = static_cast<int64_t>(misses.size());
      if (!misses.empty()) {
        const Spread miss = MedianP95Largest(misses);
        summary.landing_miss_median_mm = miss.median, summary.landing_miss_p95_mm = miss.p95, summary.landing_miss_max_mm = miss.largest;
      }
    }
  }
  if (ground) {
    summary.held_foot_steps = stance_feet->heldFootSteps();
    summary.tilted_foot_steps = stance_feet->tiltedFootSteps();
    const StanceFeet::PhaseDrift drift = stance_feet->phaseDrift();
    summary.held_phases = drift.phases;
    summary.held_turn_median_deg = drift.median_turn * kDegreesPerRadian;
    summary.held_turn_p95_deg = drift.p95_turn * kDegreesPerRadian;
    summary.held_turn_max_deg = drift.largest_turn * kDegreesPerRadian;
    summary.held_move_median_mm = drift.median_move * 1000;
    summary.held_move_p95_mm = drift.p95_move * 1000;
    summary.held_move_max_mm = drift.largest_move * 1000;
    summary.landings = drift.landings;
    summary.landing_turn_median_deg = drift.median_landing_turn * kDegreesPerRadian;
    summary.landing_turn_p95_deg = drift.p95_landing_turn * kDegreesPerRadian;
    summary.landing_turn_max_deg = drift.largest_landing_turn * kDegreesPerRadian;
    summary.unexplained_force_rms_n = std::sqrt(unexplained_force_sq / static_cast<double>(frames));
    summary.unexplained_torque_rms_nm = std::sqrt(unexplained_torque_sq / static_cast<double>(frames));
  }
  summary.joint_rms_deg = joint_count > 0 ? std::sqrt(joint_sq / static_cast<double>(joint_count)) * kDegreesPerRadian : 0;
  summary.joint_max_deg = joint_max * kDegreesPerRadian;
  summary.p1_position_rms_m = p1_position_count > 0 ? std::sqrt(p1_position_sq / static_cast<double>(p1_position_count)) : 0;
  summary.p1_angle_rms_deg = p1_angle_count > 0 ? std::sqrt(p1_angle_sq / static_cast<double>(p1_angle_count)) * kDegreesPerRadian : 0;
  summary.message = "simulated " + std::to_string(input.time_s.back() - input.time_s.front()) + " s in contact mode " +
                    std::string(ContactModeName(options.contact)) + " with " + std::string(IntegratorName(options.integrator));
  return result;
}

}  // namespace syn
