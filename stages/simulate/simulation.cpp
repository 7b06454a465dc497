#include "stages/simulate/simulation.h"

#include <cmath>
#include <sstream>

#include "common/error.h"

namespace syn {
namespace {

constexpr double kDegreesPerRadian = 180.0 / M_PI;
constexpr double kDivergedVelocity = 1e4;

double AngleBetween(const Eigen::Quaterniond& a, const Eigen::Quaterniond& b) {
  return 2.0 * std::acos(std::min(1.0, std::abs(a.normalized().dot(b.normalized()))));
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

}  // namespace

std::string_view ContactModeName(ContactMode) { return "none"; }

bool SimulateOptions::IsValid(std::string* error) const {
  const auto fail = [&](const std::string& message) {
    if (error != nullptr) *error = message;
    return false;
  };
  if (!(rate >= 10.0 && rate <= 1e5)) return fail("--rate must be in [10, 100000] Hz, got " + std::to_string(rate));
  if (!(controller.kp > 0) || !std::isfinite(controller.kp)) return fail("--kp must be > 0, got " + std::to_string(controller.kp));
  if (!(controller.kv >= 0) || !std::isfinite(controller.kv)) return fail("--kv must be >= 0, got " + std::to_string(controller.kv));
  const double cutoff = controller.hierarchy.singular_cutoff;
  if (!(cutoff > 0 && cutoff < 1)) return fail("--singular-cutoff must be in (0, 1), got " + std::to_string(cutoff));
  if (!(controller.limit_frequency > 0 && controller.limit_frequency <= 1e4)) {
    return fail("--limit-frequency must be in (0, 10000] rad/s, got " + std::to_string(controller.limit_frequency));
  }
  const double damping = controller.hierarchy.damping;
  if (!(damping >= 0 && damping < 1)) return fail("--damping must be in [0, 1), got " + std::to_string(damping));
  return true;
}

nlohmann::json SimulateOptions::ToJson() const {
  return {{"rate", rate},
          {"kp", controller.kp},
          {"kv", controller.kv},
          {"singular_cutoff", controller.hierarchy.singular_cutoff},
          {"damping", controller.hierarchy.damping},
          {"no_effort_limits", !controller.effort_limits},
          {"no_joint_limits", !controller.joint_limits},
          {"limit_frequency", controller.limit_frequency},
          {"contact", std::string(ContactModeName(contact))},
          {"targets", std::string(TargetSourceName(targets))},
          {"integrator", std::string(IntegratorName(integrator))}};
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
  out << BriefReport() << "\n  saturated joint-steps: " << saturated_entries << "\n  " << message;
  return out.str();
}

SimulationResult Simulate(const MotionData& input, const std::string& input_name, const Model& model,
                          const RobotMap& map, const SimulateOptions& options) {
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
  const TaskReferences references(input, model, tasks, options.targets);
  OperationalSpaceController controller(model, tasks, options.controller);
  FixedStepIntegrator integrator(model);
  Workspace workspace(model);

  SimulationResult result;
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
  Eigen::VectorXd tau(nu), udot(nu);
  std::vector<TaskReference> task_references;
  PostureReference posture;
  summary.steps = summary.saturated_steps = summary.saturated_entries = summary.limited_steps = 0;
  double joint_sq = 0, joint_max = 0, p1_position_sq = 0, p1_angle_sq = 0;
  int64_t joint_count = 0, p1_position_count = 0, p1_angle_count = 0;
  const auto control = [&](int64_t frame, double fraction) {
    workspace.setQ(q);
    workspace.setU(u);
    references.sample(frame, fraction, task_references, posture);
    const int saturated = controller.calcTorques(workspace, task_references, posture, tau);
    summary.saturated_entries += saturated;
    summary.saturated_steps += saturated > 0 ? 1 : 0;
    summary.limited_steps += controller.activeLimitCount() > 0 ? 1 : 0;
    workspace.calcForwardDynamics(tau, udot);
  };
  for (int64_t t = 0; t < frames; ++t) {
    control(t, 0.0);
    // Record the frame: the state, the acceleration and torques the controller commands there.
    std::copy(q.data(), q.data() + nq, out.q.begin() + t * nq);
    std::copy(u.data(), u.data() + nu, out.u.begin() + t * nu);
    std::copy(udot.data(), udot.data() + nu, out.udot.begin() + t * nu);
    std::copy(tau.data(), tau.data() + nu, out.tau.begin() + t * nu);
    MeasureErrors(workspace, tasks, input, t, task_references, out, p1_position_sq, p1_angle_sq, p1_position_count,
                  p1_angle_count);
    for (const ModelJoint& joint : model.joints()) {
      if (joint.q_index < 0 || joint.type == "free") continue;
      const double error = q[joint.q_index] - input.q[static_cast<size_t>(t * nq + joint.q_index)];
      joint_sq += error * error, ++joint_count;
      joint_max = std::max(joint_max, std::abs(error));
    }
    if (t + 1 == frames) break;
    const double interval = input.time_s[static_cast<size_t>(t + 1)] - input.time_s[static_cast<size_t>(t)];
    const int64_t steps = std::max<int64_t>(1, static_cast<int64_t>(std::ceil(interval * options.rate - 1e-9)));
    const double dt = interval / static_cast<double>(steps);
    for (int64_t step = 0; step < steps; ++step) {
      if (step > 0) control(t, static_cast<double>(step) / static_cast<double>(steps));
      integrator.step(workspace, options.integrator, tau, dt, &udot, q, u);
      ++summary.steps;
      // Any velocity above 10⁴ (rad/s or m/s) is a blown-up step, caught before Simbody sees NaN poses.
      if (!q.allFinite() || !u.allFinite() || u.cwiseAbs().maxCoeff() > kDivergedVelocity) {
        throw DataError(Location::AtFrame(input_name, t), "the simulation diverged at t = " + std::to_string(input.time_s[static_cast<size_t>(t)] + (step + 1) * dt) + " s");
      }
    }
  }
  summary.frames = frames;
  summary.joint_rms_deg = joint_count > 0 ? std::sqrt(joint_sq / static_cast<double>(joint_count)) * kDegreesPerRadian : 0;
  summary.joint_max_deg = joint_max * kDegreesPerRadian;
  summary.p1_position_rms_m = p1_position_count > 0 ? std::sqrt(p1_position_sq / static_cast<double>(p1_position_count)) : 0;
  summary.p1_angle_rms_deg = p1_angle_count > 0 ? std::sqrt(p1_angle_sq / static_cast<double>(p1_angle_count)) * kDegreesPerRadian : 0;
  summary.message = "simulated " + std::to_string(input.time_s.back() - input.time_s.front()) + " s in contact mode " +
                    std::string(ContactModeName(options.contact)) + " with " + std::string(IntegratorName(options.integrator));
  return result;
}

}  // namespace syn
