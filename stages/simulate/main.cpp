// syn-simulate IN.motion.h5 -o OUT.motion.h5 --model ROBOT.urdf --robot-map MAP.toml: the paper's
// dynamic mapping, an operational-space controller tracking the retargeted motion on the robot simulated
// in Simbody.
#include <chrono>
#include <filesystem>
#include <iostream>
#include <map>

#include "common/cli.h"
#include "common/file_bytes.h"
#include "common/intermediate_file.h"
#include "common/model.h"
#include "common/motion_file.h"
#include "common/robot_map.h"
#include "stages/simulate/simulation.h"

int main(int argc, char** argv) {
  CLI::App app{"Simulate the robot tracking a retargeted motion with the paper's operational-space controller: the "
               "robot map's tasks as strict priorities (dynamically consistent null-space projection), PD on the "
               "task references plus their acceleration, the joint posture last, gravity/Coriolis compensation and "
               "the URDF's effort limits, integrated in Simbody at a fixed rate. Writes a motion file (q, u, udot "
               "from the simulation, tau = commanded torques, landmark_error = the tasks' errors) at the input's "
               "frame times.",
               "syn-simulate"};
  syn::CommonFlags common;
  syn::AddCommonFlags(app, common);
  syn::SimulateOptions options;
  std::string input, model_path, map_path, floating_base = "auto";
  app.add_option("INPUT", input, "Retargeted motion file (syn-retarget)")->required();
  app.add_option("--model", model_path, "The robot URDF the motion was made with")->required();
  app.add_option("--robot-map", map_path, "Robot map (tasks, priorities): manifests/robots/NAME.toml")->required();
  app.add_option("--floating-base", floating_base, "auto | free | fixed, as for syn-retarget")->capture_default_str();
  app.add_option("--contact", options.contact,
                 "none: the paper's setting, the floating base driven like a task and the ground only a reference "
                 "plane; ground: the robot map's sole points on a compliant floor with friction (mu 0.8), the base "
                 "unactuated, the base's share of the controller's forces split into sole forces inside their "
                 "friction cones; a fall (pelvis under 60 % of the reference's height) stops with exit 1")
      ->transform(CLI::CheckedTransformer(std::map<std::string, syn::ContactMode>{{"none", syn::ContactMode::kNone},
                                                                                  {"ground", syn::ContactMode::kGround}}))
      ->default_str("none");
  app.add_option("--rate", options.rate, "Control and integration rate, Hz (paper: 1 kHz)")->capture_default_str();
  app.add_option("--kp", options.controller.kp, "Task and posture stiffness, 1/s² (paper's code: 350)")
      ->capture_default_str();
  app.add_option("--kv", options.controller.kv, "Task and posture damping, 1/s (paper's code: 25)")->capture_default_str();
  app.add_option("--independence-cutoff", options.controller.hierarchy.independence_cutoff,
                 "Drop a level's task rows once the most independent left has less than this fraction of its "
                 "mobility (unit-diagonal J A^-1 J^T pivot) not given by the rows kept before it")
      ->capture_default_str();
  app.add_option("--damping", options.controller.hierarchy.damping,
                 "mu of the task forces' damped inverse lambda/(lambda^2+mu^2) on the kept rows' unit-diagonal J A^-1 J^T "
                 "(bounds the force at a singular limb; 0: undamped)")
      ->capture_default_str();
  bool no_effort_limits = false;
  app.add_flag("--no-effort-limits", no_effort_limits,
               "Do not clamp joint torques to the URDF's effort limits (for diagnosis: what the limits cost)");
  bool no_balance = false;
  app.add_flag("--no-balance", no_balance,
               "Ground mode: track the retargeted motion as it is, without leaning the body above the legs so that "
               "its zero-moment point stays inside the feet (for diagnosis)");
  app.add_option("--balance-gain", options.balance_gain,
                 "Ground mode: rate (1/s) at which the capture point returns to the balance plan's")
      ->capture_default_str();
  app.add_option("--step-adjustment", options.step_adjustment,
                 "Ground mode: a swinging foot lands up to this far (m) off its planned place, by the capture point's "
                 "error predicted at its touchdown, and the plan walks on from there (0: no stepping)")
      ->capture_default_str();
  app.add_option("--swing-lift", options.swing_lift,
                 "Ground mode: a swinging foot is carried up to this much (m) higher than the source's, most at "
                 "mid-swing, so that it does not scuff the floor and land short (0: the source's height)")
      ->capture_default_str();
  app.add_option("--support-margin", options.support_margin,
                 "Ground mode: how far (m) inside the feet the balance plan keeps its zero-moment point (each "
                 "support-polygon vertex moved this far toward its centroid), room for the capture-point feedback")
      ->capture_default_str();
  app.add_option("--centre-line-turn", options.centre_line_turn,
                 "Ground mode: where the reference's base turns more than this (deg) within half a second either side, "
                 "the balance plan keeps its zero-moment point on the soles' centre lines, the ankles' room either way "
                 "(1e6: never)")
      ->capture_default_str();
  app.add_option("--moment-weight", options.moment_weight,
                 "Ground mode: where the soles cannot give the whole base wrench the controller plans, how much the "
                 "planned sole forces favour its moments over its force (1: N·m against N one to one; a brisk walk "
                 "that tips over may stay up at 2, at some cost to others: README)")
      ->capture_default_str();
  bool no_swing_heading = false;
  app.add_flag("--no-swing-heading", no_swing_heading,
               "Ground mode: leave a swinging foot's heading to its task at the map's priority instead of a level "
               "above the tasks (for diagnosis: feet then land turned more often)");
  app.add_option("--swing-landing", options.swing_landing,
                 "Ground mode: over this last fraction of a swing (the source's lift-off to touchdown) the swinging "
                 "foot's position is kept exactly with its heading, so that it lands where the stepping aims it (0: "
                 "left to its task)")
      ->capture_default_str();
  std::string fall_record;
  app.add_option("--fall-record", fall_record,
                 "Ground mode: when the robot falls, write the frames simulated before the fall to this motion file "
                 "(for looking at how it fell; the output is still not written, and the stage still exits 1)");
  std::string control_trace;
  app.add_option("--control-trace", control_trace,
                 "Ground mode: write the balance loop per control step to this CSV (the level's force and zero-moment "
                 "points, the planned and applied sole forces; columns in stages/simulate/control_trace.h), whether the "
                 "robot stays up or falls");
  bool no_joint_limits = false;
  app.add_flag("--no-joint-limits", no_joint_limits,
               "Do not hold joints inside the URDF's position limits (for diagnosis: without them a straightening "
               "knee can be carried onto its mirrored branch)");
  app.add_option("--limit-frequency", options.controller.limit_frequency,
                 "Natural frequency (rad/s) of the critically damped walls at the joints' position limits")
      ->capture_default_str();
  app.parse_complete_callback([&] {
    options.controller.effort_limits = !no_effort_limits;
    options.controller.joint_limits = !no_joint_limits;
    options.balance = !no_balance;
    options.swing_heading = !no_swing_heading;
  });
  app.add_option("--targets", options.targets,
                 "kinematic: track the link poses of the retargeted q; landmarks: track the landmark targets "
                 "(velocity/acceleration feedforward from the retargeted q either way)")
      ->transform(CLI::CheckedTransformer(std::map<std::string, syn::TargetSource>{
          {"kinematic", syn::TargetSource::kKinematic}, {"landmarks", syn::TargetSource::kLandmarks}}))
      ->default_str("kinematic");
  app.add_option("--integrator", options.integrator,
                 "euler: semi-implicit Euler (1 dynamics evaluation per step); rk4: classical Runge-Kutta (4)")
      ->transform(CLI::CheckedTransformer(std::map<std::string, syn::Integrator>{
          {"euler", syn::Integrator::kSemiImplicitEuler}, {"rk4", syn::Integrator::kRungeKutta4}}))
      ->default_str("euler");
  const auto parameters = [&] {
    syn::RequireValid(options);
    return syn::WithFloatingBase(options.ToJson(), floating_base);
  };
  return syn::RunTool(app, argc, argv, parameters, [&] {
    syn::RequireValid(options);
    if (!fall_record.empty() && options.contact != syn::ContactMode::kGround) {
      throw syn::UsageError("--fall-record needs --contact ground (only a robot on the ground can fall)");
    }
    if (!fall_record.empty() && std::filesystem::path(fall_record) == std::filesystem::path(common.output)) {
      throw syn::UsageError("--fall-record must name another file than -o (a fall leaves no output)");
    }
    if (!control_trace.empty() && (options.contact != syn::ContactMode::kGround || !options.balance)) {
      throw syn::UsageError("--control-trace needs --contact ground with its balance controller (no --no-balance)");
    }
    for (const std::string* other : {&common.output, &fall_record}) {
      if (!control_trace.empty() && !other->empty() && std::filesystem::path(control_trace) == std::filesystem::path(*other)) {
        throw syn::UsageError("--control-trace must name another file than -o and --fall-record");
      }
    }
    // Before the simulation, so that a run that falls says with what it fell.
    if (common.verbose) std::cerr << "syn-simulate: parameters " << syn::CanonicalJson(parameters()) << "\n";
    const syn::Model model = syn::LoadModel(model_path, floating_base);
    syn::PrintWarnings("syn-simulate", model.warnings());
    const syn::RobotMap map = syn::LoadRobotMap(map_path);
    const syn::MotionData motion = syn::ReadMotionFile(input);
    syn::Provenance provenance;
    provenance.schema = syn::kMotionSchema;
    provenance.schema_version = syn::kMotionSchemaVersion;
    provenance.producer = std::string("syn-simulate ") + syn::kVersion;
    provenance.parameters = parameters();
    provenance.inputs = nlohmann::json::array(
        {syn::DescribeInput(input), syn::DescribeInput(model_path), syn::DescribeInput(map_path)});
    syn::SimulationResult result;
    syn::ControlTrace trace;
    syn::ControlTrace* tracing = control_trace.empty() ? nullptr : &trace;
    const auto write_trace = [&] {
      if (tracing == nullptr) return;
      syn::WriteFileAtomically(control_trace, trace.ToCsv());
      std::cerr << "syn-simulate: " << trace.rows().size() << " control steps written to " << control_trace << "\n";
    };
    const auto start = std::chrono::steady_clock::now();
    try {
      result = syn::Simulate(motion, input, model, map, options, tracing);
    } catch (const syn::FallError& fall) {
      write_trace();
      if (!fall_record.empty()) {
        syn::IntermediateWriter record(fall_record, provenance);
        syn::WriteMotionData(record, fall.beforeFall());
        record.commit();
        std::cerr << "syn-simulate: the " << fall.beforeFall().frames() << " frames before the fall written to " << fall_record
                  << "\n";
      }
      throw;
    }
    const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    write_trace();

    syn::IntermediateWriter writer(common.output, provenance);
    syn::WriteMotionData(writer, result.motion);
    writer.commit();
    if (common.verbose) std::cerr << result.summary.FullReport() << "\n";
    const double simulated = motion.time_s.back() - motion.time_s.front();
    std::cerr << "syn-simulate: " << input << " -> " << common.output << ": " << result.summary.BriefReport() << "; "
              << (wall > 0 ? simulated / wall : 0.0) << "x real time\n";
  });
}
