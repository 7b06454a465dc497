#include "stages/retarget/retarget.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <sstream>

#include <Eigen/Geometry>

#include "common/configuration_space.h"
#include "common/error.h"
#include "common/foot_sliding.h"
#include "common/percentile.h"
#include "common/markers_file.h"
#include "stages/retarget/branch_joints.h"
#include "stages/retarget/foot_yaw_range.h"
#include "stages/retarget/frame_ik.h"
#include "stages/retarget/landmarks.h"
#include "stages/retarget/stance_alignment.h"
#include "stages/retarget/terrain_flattening.h"
#include "stages/retarget/trajectory_refinement.h"
#include "stages/retarget/velocity_estimation.h"

namespace syn {
namespace {

// Frames with no target at all kept the previous solution; interpolate them
// between their neighbours when the gap is short, refuse when it is not.
void BridgeGaps(const Model& model, const std::vector<double>& time_s, const std::vector<int64_t>& bridged,
                double max_bridge, const std::string& source, std::vector<double>& q) {
  const int64_t nq = model.nq();
  const int64_t frames = static_cast<int64_t>(time_s.size());
  const ConfigurationShape shape = ConfigurationShape::Of(model.hasFreeBase(), static_cast<int>(nq));
  size_t k = 0;
  while (k < bridged.size()) {
    size_t end = k;
    while (end + 1 < bridged.size() && bridged[end + 1] == bridged[end] + 1) ++end;
    const int64_t first = bridged[k], last = bridged[end];
    const int64_t before = first - 1, after = last + 1;
    const double span = time_s[static_cast<size_t>(std::min(after, frames - 1))] -
                        time_s[static_cast<size_t>(std::max<int64_t>(before, 0))];
    if (span > max_bridge || before < 0 || after >= frames) {
      throw DataError(Location::InFile(source),
                      "no landmark at all from " + std::to_string(time_s[static_cast<size_t>(first)]) + " s to " +
                          std::to_string(time_s[static_cast<size_t>(last)]) + " s (" +
                          (before < 0 || after >= frames ? std::string("at the trial's edge") : "longer than --max-bridge") +
                          "); trim the trial or fill the gaps at ingest");
    }
    for (int64_t t = first; t <= last; ++t) {
      const double fraction = (time_s[static_cast<size_t>(t)] - time_s[static_cast<size_t>(before)]) / span;
      Interpolate(shape, &q[static_cast<size_t>(before * nq)], &q[static_cast<size_t>(after * nq)], fraction,
                  &q[static_cast<size_t>(t * nq)]);
    }
    k = end + 1;
  }
}


// The robot map's tasks that the capture's landmarks can feed, as the IK tracks them.
struct TrackedTasks {
  std::vector<IkTask> ik;
  std::vector<int64_t> landmark;  // index into LandmarkTrajectories, per task
  std::vector<int> priority;      // 1..3, per task
  size_t size() const { return ik.size(); }
};

TrackedTasks SelectTasks(const RetargetInputs& inputs, const LandmarkTrajectories& landmarks,
                         const RetargetOptions& options, std::vector<std::string>& notes) {
  TrackedTasks tasks;
  for (const RobotTask& task : inputs.map.tasks) {
    const auto found = std::find(landmarks.names.begin(), landmarks.names.end(), task.landmark);
    if (found == landmarks.names.end()) {
      notes.push_back("marker set '" + inputs.marker_set.name + "' has no " + task.landmark + " landmark: task dropped");
      continue;
    }
    const int64_t landmark = found - landmarks.names.begin();
    IkTask ik_task;
    ik_task.link = inputs.model.findLinkIndex(task.link);
    ik_task.type = task.type;
    ik_task.weight = inputs.map.priority_weights[static_cast<size_t>(task.priority - 1)] * task.weight;
    if (!landmarks.has_orientation[static_cast<size_t>(landmark)] && task.type != TaskType::kPosition) {
      notes.push_back(task.landmark + " has no orientation in this marker set: tracked by position only");
      ik_task.type = TaskType::kPosition;
    }
    tasks.ik.push_back(ik_task);
    tasks.landmark.push_back(landmark);
    tasks.priority.push_back(task.priority);
  }
  if (tasks.ik.empty()) throw DataError(Location::InFile(options.robot_map), "no task of the robot map can be tracked");
  return tasks;
}

// The frame nearest --reference-time, or the first frame where every tracked landmark is present.
int64_t FindReferenceFrame(const RetargetInputs& inputs, const LandmarkTrajectories& landmarks,
                           const TrackedTasks& tasks, const RetargetOptions& options) {
  int64_t reference = -1;
  const int64_t frames = landmarks.frames;
  if (options.reference_time >= 0) {
    double best = std::numeric_limits<double>::infinity();
    for (int64_t t = 0; t < frames; ++t) {
      const double distance = std::abs(inputs.capture.time_s[static_cast<size_t>(t)] - options.reference_time);
      if (distance < best) best = distance, reference = t;
    }
  } else {
    for (int64_t t = 0; t < frames && reference < 0; ++t) {
      bool all = true;
      for (int64_t landmark : tasks.landmark) all = all && SampleAt(landmarks, t, landmark).valid;
      if (all) reference = t;
    }
  }
  if (reference < 0) {
    throw DataError(Location::InFile(inputs.capture_path), "no frame has every tracked landmark; give --reference-time");
  }
  return reference;
}

// The capture's calibration frame as one-frame landmarks; frames = 0 when it has none.
LandmarkTrajectories CalibrationFrameLandmarks(const RetargetInputs& inputs) {
  const MarkerData& capture = inputs.capture;
  if (capture.calibration_body_pose.empty()) return {};
  MarkerData calibration;
  calibration.rate_hz = capture.rate_hz;
  calibration.time_s = {0.0};
  calibration.labels = capture.labels;
  calibration.points.assign(capture.labels.size() * 3, std::nan(""));
  calibration.bodies = capture.bodies;
  calibration.body_parents = capture.body_parents;
  calibration.body_pose = capture.calibration_body_pose;
  // Not turned with the take when its floor is levelled: a BVH's calibration frame is its converter's rest
  // pose, upright in the file's axes, not a subject standing on the capture's floor.
  return ComputeLandmarks(calibration, inputs.marker_set, inputs.capture_path);
}

// The capture's calibration frame as one-frame landmarks, when the map has a [calibration_stance] and no
// --reference-time overrides it; frames = 0 when it is not used.
LandmarkTrajectories CalibrationLandmarks(const RetargetInputs& inputs, const TrackedTasks& tasks,
                                          const RetargetOptions& options, std::vector<std::string>& notes) {
  if (!inputs.map.calibration_stance || options.reference_time >= 0) return {};
  LandmarkTrajectories landmarks = CalibrationFrameLandmarks(inputs);
  if (landmarks.frames == 0) {
    notes.push_back("the robot map has a calibration stance, but the capture has no calibration frame "
                    "(syn-ingest --drop-first-frame keeps a BVH's): the first complete frame is the reference");
    return {};
  }
  for (int64_t landmark : tasks.landmark) {
    if (!SampleAt(landmarks, 0, landmark).valid) {
      notes.push_back("landmark " + landmarks.names[static_cast<size_t>(landmark)] +
                      " is missing in the calibration frame: the first complete frame is the reference");
      return {};
    }
  }
  return landmarks;
}

// The coordinate of q that moves the whole robot straight up (a free base's z, or the unactuated prismatic
// joint of a virtual base chain such as HRP-4C's), found by raising it 1 m at q and watching `lowest_sole`;
// -1 when there is none.
template <typename LowestSole>
int64_t VerticalCoordinate(const Model& model, const Eigen::VectorXd& q, const LowestSole& lowest_sole) {
  if (model.hasFreeBase()) return 6;
  const double lowest = lowest_sole(q);
  for (const ModelJoint& joint : model.joints()) {
    if (joint.type != "prismatic" || model.actuatedVelocities()[static_cast<size_t>(joint.u_index)]) continue;
    Eigen::VectorXd raised = q;
    raised[joint.q_index] += 1.0;
    if (std::abs(lowest_sole(raised) - lowest - 1.0) < 1e-9) return joint.q_index;
  }
  return -1;
}

// The height of the lowest sole point of the robot map's feet at q (sets the workspace to q).
double LowestSolePoint(const Model& model, Workspace& workspace, const RobotMap& map, const Eigen::VectorXd& q) {
  workspace.setQ(q);
  double lowest = std::numeric_limits<double>::infinity();
  for (const RobotFoot& foot : map.feet) {
    const Eigen::Isometry3d pose = workspace.findLinkPose(model.findLinkIndex(foot.link));
    for (const auto& point : foot.sole_points) lowest = std::min(lowest, (pose * Eigen::Vector3d(point[0], point[1], point[2])).z());
  }
  return lowest;
}

// One of the robot map's stances (joint -> q, others at the model's default) with the soles on the ground
// (z = 0).
Eigen::VectorXd GroundedStance(const Model& model, Workspace& workspace, const RobotMap& map,
                               const std::map<std::string, double>& stance) {
  const auto joint_names = model.coordinateNames();
  Eigen::VectorXd q_ref = model.defaultQ();
  for (const auto& [joint, value] : stance) {
    const auto found = std::find(joint_names.begin(), joint_names.end(), joint);
    q_ref[found - joint_names.begin()] = value;
  }
  if (map.feet.empty()) return q_ref;
  const auto lowest_sole = [&](const Eigen::VectorXd& q) { return LowestSolePoint(model, workspace, map, q); };
  const double lowest = lowest_sole(q_ref);
  const int64_t vertical = VerticalCoordinate(model, q_ref, lowest_sole);
  if (vertical >= 0) q_ref[vertical] -= lowest;
  return q_ref;
}

// The calibration frame turned about the vertical and moved horizontally so that the subject faces, and
// stands, where the take starts (at `take_frame`): the take then begins near the reference stance instead of
// a turn away from it (cgspeed's Daz-friendly CMU conversions record the T-pose facing elsewhere).
void TurnCalibrationToTake(const LandmarkTrajectories& landmarks, int64_t take_frame, LandmarkTrajectories& calibration) {
  const auto pelvis_at = std::find(landmarks.names.begin(), landmarks.names.end(), "pelvis");
  if (pelvis_at == landmarks.names.end()) return;
  const LandmarkSample pelvis_calibration = SampleAt(calibration, 0, pelvis_at - landmarks.names.begin());
  const LandmarkSample pelvis_take = SampleAt(landmarks, take_frame, pelvis_at - landmarks.names.begin());
  if (!pelvis_calibration.valid || !pelvis_take.valid || !pelvis_calibration.has_orientation ||
      !pelvis_take.has_orientation) {
    return;
  }
  // The pelvis' turn between the two frames, about the vertical: the yaw of the rotation nearest to it that
  // turns about Z only. (The feet give no heading mid-stride, one ahead of the other.)
  const Eigen::Matrix3d between = (pelvis_take.orientation * pelvis_calibration.orientation.conjugate()).toRotationMatrix();
  const double yaw = std::atan2(between(1, 0) - between(0, 1), between(0, 0) + between(1, 1));
  const Eigen::Quaterniond turn(Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()));
  Eigen::Vector3d shift = pelvis_take.position - turn * pelvis_calibration.position;
  shift.z() = 0;
  for (int64_t l = 0; l < calibration.count(); ++l) {
    double* pose = &calibration.pose[static_cast<size_t>(l * 7)];
    const Eigen::Vector3d position = turn * Eigen::Vector3d(pose[0], pose[1], pose[2]) + shift;
    const Eigen::Quaterniond orientation = turn * Eigen::Quaterniond(pose[3], pose[4], pose[5], pose[6]);
    pose[0] = position.x(), pose[1] = position.y(), pose[2] = position.z();
    pose[3] = orientation.w(), pose[4] = orientation.x(), pose[5] = orientation.y(), pose[6] = orientation.z();
  }
}

// The feet's orientation targets held within the turn their legs can make about the pelvis
// (foot_yaw_range.h): the pelvis task and, per held foot, its task, its range and its orientation relative
// to the pelvis link's in the reference stance. No feet where nothing is held.
struct FootYawHolds {
  struct Foot {
    int task = -1;
    YawRange range;
    Eigen::Quaterniond reference = Eigen::Quaterniond::Identity();
  };
  int pelvis_task = -1;
  std::vector<Foot> feet;
  int64_t held_foot_frames = 0;  // foot-frames whose target turned further
};

// The holds for the tracked feet (`foot_tasks`, per robot-map foot: -1 where none) whose targets have an
// orientation, when the "pelvis" landmark is tracked as a pose.
FootYawHolds PlanFootYawHolds(const Model& model, Workspace& workspace, const TrackedTasks& tasks,
                              const std::vector<int>& foot_tasks, const LandmarkTrajectories& landmarks,
                              const Eigen::VectorXd& q_ref, const std::vector<Eigen::Isometry3d>& link_reference) {
  FootYawHolds holds;
  for (size_t i = 0; i < tasks.size(); ++i) {
    if (landmarks.names[static_cast<size_t>(tasks.landmark[i])] == "pelvis" && tasks.ik[i].type == TaskType::kPose) {
      holds.pelvis_task = static_cast<int>(i);
    }
  }
  if (holds.pelvis_task < 0) return holds;
  const size_t pelvis = static_cast<size_t>(holds.pelvis_task);
  for (int task : foot_tasks) {
    if (task < 0 || tasks.ik[static_cast<size_t>(task)].type == TaskType::kPosition) continue;
    const size_t foot = static_cast<size_t>(task);
    holds.feet.push_back({task, FootYawRange(model, workspace, q_ref, tasks.ik[pelvis].link, tasks.ik[foot].link),
                          Eigen::Quaterniond(link_reference[pelvis].linear().transpose() * link_reference[foot].linear())});
  }
  return holds;
}

// One frame's IK targets: each landmark's motion since the reference frame, turned and scaled, applied to
// its link's reference pose, the feet's turns held (`holds`). Stores them in the motion's landmark_targets;
// false when none is present.
bool FrameTargets(const LandmarkTrajectories& landmarks, const TrackedTasks& tasks,
                  const std::vector<LandmarkSample>& reference_samples, const std::vector<Eigen::Isometry3d>& link_reference,
                  const StanceAlignment& alignment, int64_t t, FootYawHolds& holds, std::vector<IkTarget>& targets,
                  MotionData& motion) {
  const size_t task_count = tasks.size();
  bool any = false;
  for (size_t i = 0; i < task_count; ++i) {
    const LandmarkSample sample = SampleAt(landmarks, t, tasks.landmark[i]);
    const LandmarkSample& ref = reference_samples[i];
    IkTarget& target = targets[i];
    target.active = sample.valid && ref.valid;
    target.has_orientation = sample.has_orientation && ref.has_orientation;
    if (!target.active) continue;
    any = true;
    target.position = link_reference[i].translation() + RobotDisplacement(alignment, landmarks, tasks.landmark[i], t, sample, ref);
    if (target.has_orientation) {
      const Eigen::Matrix3d relative = (sample.orientation * ref.orientation.conjugate()).toRotationMatrix();
      target.orientation =
          Eigen::Quaterniond(alignment.heading * relative * alignment.heading.transpose() * link_reference[i].linear());
    }
  }
  const IkTarget* pelvis = holds.pelvis_task >= 0 ? &targets[static_cast<size_t>(holds.pelvis_task)] : nullptr;
  for (const FootYawHolds::Foot& foot : holds.feet) {
    IkTarget& target = targets[static_cast<size_t>(foot.task)];
    if (pelvis->active && pelvis->has_orientation && target.active && target.has_orientation &&
        HoldFootYaw(pelvis->orientation, foot.reference, foot.range, target.orientation)) {
      ++holds.held_foot_frames;
    }
  }
  for (size_t i = 0; i < task_count; ++i) {
    const IkTarget& target = targets[i];
    if (!target.active) continue;
    double* stored = &motion.landmark_targets[(static_cast<size_t>(t) * task_count + i) * 7];
    stored[0] = target.position.x(), stored[1] = target.position.y(), stored[2] = target.position.z();
    if (target.has_orientation) {
      stored[3] = target.orientation.w(), stored[4] = target.orientation.x();
      stored[5] = target.orientation.y(), stored[6] = target.orientation.z();
    }
  }
  return any;
}

// The empty motion of the model for the capture's frames, with room for the tasks' targets and errors.
MotionData EmptyMotion(const Model& model, const MarkerData& capture, const LandmarkTrajectories& landmarks,
                       const TrackedTasks& tasks) {
  MotionData motion;
  const int64_t frames = landmarks.frames;
  motion.time_s.assign(capture.time_s.begin(), capture.time_s.end());
  motion.coordinate_names = model.coordinateNames();
  motion.velocity_names = model.velocityNames();
  motion.model_name = model.name();
  motion.model_sha256 = model.sourceSha256();
  motion.total_mass = model.totalMass();
  motion.q.resize(static_cast<size_t>(frames * model.nq()));
  for (size_t i = 0; i < tasks.size(); ++i) motion.landmark_names.push_back(landmarks.names[static_cast<size_t>(tasks.landmark[i])]);
  motion.landmark_targets.assign(static_cast<size_t>(frames) * tasks.size() * 7, std::nan(""));
  motion.landmark_error.assign(static_cast<size_t>(frames) * tasks.size() * 2, std::nan(""));
  return motion;
}

// Per-frame IK over the whole capture, each frame warm-started from the previous one. Frames with no
// target keep the previous solution and are listed in `bridged`; `frame_targets` keeps what each solved
// frame tracked, for the refinement.
void SolveFrames(const LandmarkTrajectories& landmarks, const TrackedTasks& tasks,
                 const std::vector<LandmarkSample>& reference_samples, const std::vector<Eigen::Isometry3d>& link_reference,
                 const StanceAlignment& alignment, const Eigen::VectorXd& q_start, double velocity_limit_scale,
                 FootYawHolds& holds, FrameIk& ik, MotionData& motion, std::vector<std::vector<IkTarget>>& frame_targets,
                 std::vector<int64_t>& bridged, RetargetSummary& report) {
  const int64_t frames = landmarks.frames, nq = static_cast<int64_t>(q_start.size());
  std::vector<IkTarget> targets(tasks.size());
  Eigen::VectorXd q = q_start;
  double last_solved_time = std::nan("");  // the first solve may travel from q_start freely
  for (int64_t t = 0; t < frames; ++t) {
    if (!FrameTargets(landmarks, tasks, reference_samples, link_reference, alignment, t, holds, targets, motion)) {
      bridged.push_back(t);
      ik.forgetHistory();
    } else {
      const double step_time = std::isfinite(last_solved_time) ? velocity_limit_scale *
                                                                     (motion.time_s[static_cast<size_t>(t)] - last_solved_time)
                                                               : 0.0;
      FrameIkSummary solved = ik.solve(targets, q, step_time);
      report.mean_ik_iterations += solved.iterations;
      // The first frame travels from the start stance, far from its answer: solve it again from its
      // own result until it settles, or the next frames would finish the journey as a jump.
      for (int again = 0; !std::isfinite(last_solved_time) && again < 10; ++again) {
        ik.forgetHistory();
        const FrameIkSummary more = ik.solve(targets, q, 0.0);
        report.mean_ik_iterations += more.iterations;
        if (more.final_cost > (1 - 1e-6) * solved.final_cost) break;
        solved = more;
      }
      if (!std::isfinite(last_solved_time)) ik.forgetHistory();
      last_solved_time = motion.time_s[static_cast<size_t>(t)];
      frame_targets[static_cast<size_t>(t)] = targets;
    }
    std::copy(q.data(), q.data() + nq, motion.q.begin() + t * nq);
  }
  report.mean_ik_iterations /= static_cast<double>(std::max<int64_t>(1, frames - static_cast<int64_t>(bridged.size())));
}

// Each task's position and angle error on the final trajectory, stored per frame and summarised per
// priority level.
void MeasureLandmarkErrors(FrameIk& ik, const TrackedTasks& tasks, const std::vector<std::vector<IkTarget>>& frame_targets,
                           int64_t nq, MotionData& motion, RetargetSummary& report) {
  const size_t task_count = tasks.size();
  std::array<std::vector<double>, 3> position_by_level, angle_by_level;
  std::vector<double> position_error, angle_error;
  Eigen::VectorXd q(nq);
  for (int64_t t = 0; t < motion.frames(); ++t) {
    const std::vector<IkTarget>& frame = frame_targets[static_cast<size_t>(t)];
    if (frame.empty()) continue;
    q = Eigen::Map<const Eigen::VectorXd>(&motion.q[static_cast<size_t>(t * nq)], nq);
    ik.measureErrors(frame, q, position_error, angle_error);
    for (size_t i = 0; i < task_count; ++i) {
      motion.landmark_error[(static_cast<size_t>(t) * task_count + i) * 2] = position_error[i];
      motion.landmark_error[(static_cast<size_t>(t) * task_count + i) * 2 + 1] = angle_error[i];
      position_by_level[static_cast<size_t>(tasks.priority[i] - 1)].push_back(position_error[i]);
      angle_by_level[static_cast<size_t>(tasks.priority[i] - 1)].push_back(angle_error[i]);
    }
  }
  for (size_t level = 0; level < 3; ++level) {
    report.median_position_error[level] = NearestRankPercentile(position_by_level[level], 0.5);
    report.p95_position_error[level] = NearestRankPercentile(position_by_level[level], 0.95);
    report.median_angle_error[level] = NearestRankPercentile(angle_by_level[level], 0.5);
    report.p95_angle_error[level] = NearestRankPercentile(angle_by_level[level], 0.95);
  }
}

// Velocities, accelerations and the torques that produce them (Simbody inverse dynamics); with the
// source's contacts, the base's residual split into contact forces and the unexplained rest
// (contact_forces.h).
void ComputeDynamics(const Model& model, Workspace& workspace, const RobotMap& map, const ContactForceOptions& options,
                     MotionData& motion, RetargetSummary& report) {
  const int64_t frames = motion.frames(), nq = model.nq(), nu = model.nu();
  EstimateVelocities(model, motion.time_s, motion.q, motion.u, motion.udot);
  motion.tau.resize(static_cast<size_t>(frames * nu));
  ContactForceSplit split(model, map.feet, options);
  const bool splitting = split.hasBase() && !motion.contact_feet.empty();
  const size_t feet = motion.contact_feet.size();
  if (splitting) {
    motion.contact_force.assign(static_cast<size_t>(frames) * feet * 3, 0.0);
    motion.unexplained_wrench.assign(static_cast<size_t>(frames) * 6, 0.0);
  }
  ContactForceFrame forces;
  Eigen::VectorXd frame_q(nq), frame_u(nu), frame_udot(nu), frame_tau(nu);
  double residual_force = 0, residual_moment = 0, unexplained_force = 0, unexplained_moment = 0;
  for (int64_t t = 0; t < frames; ++t) {
    frame_q = Eigen::Map<const Eigen::VectorXd>(&motion.q[static_cast<size_t>(t * nq)], nq);
    frame_u = Eigen::Map<const Eigen::VectorXd>(&motion.u[static_cast<size_t>(t * nu)], nu);
    frame_udot = Eigen::Map<const Eigen::VectorXd>(&motion.udot[static_cast<size_t>(t * nu)], nu);
    workspace.setQ(frame_q);
    workspace.setU(frame_u);
    workspace.calcInverseDynamics(frame_udot, frame_tau);
    std::copy(frame_tau.data(), frame_tau.data() + nu, motion.tau.begin() + t * nu);
    if (!splitting) continue;
    split.split(workspace, frame_u, frame_tau, &motion.contact[static_cast<size_t>(t) * feet], forces);
    for (size_t f = 0; f < feet; ++f) {
      std::copy(forces.foot_force[f].data(), forces.foot_force[f].data() + 3,
                motion.contact_force.begin() + static_cast<std::ptrdiff_t>((static_cast<size_t>(t) * feet + f) * 3));
    }
    std::copy(forces.unexplained.data(), forces.unexplained.data() + 6,
              motion.unexplained_wrench.begin() + t * 6);
    residual_moment += forces.residual.head<3>().norm(), residual_force += forces.residual.tail<3>().norm();
    unexplained_moment += forces.unexplained.head<3>().norm(), unexplained_force += forces.unexplained.tail<3>().norm();
  }
  if (splitting && frames > 0) {
    report.forces_split = true;
    report.mean_residual_force = residual_force / static_cast<double>(frames);
    report.mean_residual_moment = residual_moment / static_cast<double>(frames);
    report.mean_unexplained_force = unexplained_force / static_cast<double>(frames);
    report.mean_unexplained_moment = unexplained_moment / static_cast<double>(frames);
  }
}

// Continuity: the largest per-frame change of any joint coordinate.
void FindWorstJointStep(const Model& model, const MotionData& motion, RetargetSummary& report) {
  const int64_t nq = model.nq();
  const int first_joint = model.hasFreeBase() ? 7 : 0;
  for (int64_t t = 1; t < motion.frames(); ++t) {
    for (int64_t i = first_joint; i < nq; ++i) {
      const double step = std::abs(motion.q[static_cast<size_t>(t * nq + i)] - motion.q[static_cast<size_t>((t - 1) * nq + i)]);
      if (step > report.worst_joint_step) {
        report.worst_joint_step = step;
        report.worst_joint_step_name = motion.coordinate_names[static_cast<size_t>(i)] + " at " +
                                       std::to_string(motion.time_s[static_cast<size_t>(t)]) + " s";
      }
    }
  }
}

// Per robot-map foot, the index of its side's "<side>_foot" landmark (-1: the marker set has none).
std::vector<int64_t> FootLandmarks(const RobotMap& map, const LandmarkTrajectories& landmarks) {
  std::vector<int64_t> indices;
  for (const RobotFoot& foot : map.feet) {
    const auto found = std::find(landmarks.names.begin(), landmarks.names.end(), foot.side + "_foot");
    indices.push_back(found == landmarks.names.end() ? -1 : found - landmarks.names.begin());
  }
  return indices;
}

// Per robot-map foot, its side's "<side>_foot" landmark position per frame (NaN where missing, and in every
// frame when the marker set has no such landmark: `missing` then names it).
std::vector<std::vector<Eigen::Vector3d>> FootPositions(const RobotMap& map, const LandmarkTrajectories& landmarks,
                                                        std::vector<std::string>* missing) {
  const std::vector<int64_t> indices = FootLandmarks(map, landmarks);
  std::vector<std::vector<Eigen::Vector3d>> positions(map.feet.size());
  for (size_t f = 0; f < map.feet.size(); ++f) {
    positions[f].assign(static_cast<size_t>(landmarks.frames), Eigen::Vector3d::Constant(std::nan("")));
    if (indices[f] < 0) {
      if (missing != nullptr) missing->push_back(map.feet[f].side + "_foot");
      continue;
    }
    for (int64_t t = 0; t < landmarks.frames; ++t) positions[f][static_cast<size_t>(t)] = SampleAt(landmarks, t, indices[f]).position;
  }
  return positions;
}

// The source's foot contacts, one column per robot foot (its side's "<side>_foot" landmark; a side the
// marker set has no foot landmark for is never in contact).
FootContacts SourceContacts(const RobotMap& map, const LandmarkTrajectories& landmarks, const std::vector<double>& time_s,
                            const RetargetOptions& options, std::vector<std::string>& notes) {
  std::vector<std::string> missing;
  const std::vector<std::vector<Eigen::Vector3d>> positions = FootPositions(map, landmarks, &missing);
  for (const std::string& name : missing) notes.push_back("marker set has no " + name + " landmark: that foot is never in contact");
  return DetectContacts(positions, time_s, options.contact);
}

// The task tracking each robot foot's link with its side's "<side>_foot" landmark (-1: none).
std::vector<int> FootTasks(const RobotMap& map, const Model& model, const LandmarkTrajectories& landmarks,
                           const TrackedTasks& tasks) {
  std::vector<int> foot_task(map.feet.size(), -1);
  for (size_t f = 0; f < map.feet.size(); ++f) {
    for (size_t i = 0; i < tasks.size(); ++i) {
      if (landmarks.names[static_cast<size_t>(tasks.landmark[i])] == map.feet[f].side + "_foot" &&
          tasks.ik[i].link == model.findLinkIndex(map.feet[f].link)) {
        foot_task[f] = static_cast<int>(i);
      }
    }
  }
  return foot_task;
}

// The target a task stored for frame t (motion.landmark_targets): its position (NaN when the landmark was
// missing) and, when the landmark has one, its orientation; false when it has none (the pose keeps identity).
bool StoredTarget(const MotionData& motion, int64_t t, int task, Eigen::Isometry3d* pose) {
  const double* target = &motion.landmark_targets[(static_cast<size_t>(t) * motion.landmark_names.size() + static_cast<size_t>(task)) * 7];
  *pose = Eigen::Isometry3d::Identity();
  pose->translation() = Eigen::Vector3d(target[0], target[1], target[2]);
  if (!std::isfinite(target[3])) return false;
  pose->linear() = Eigen::Quaterniond(target[3], target[4], target[5], target[6]).normalized().toRotationMatrix();
  return true;
}

// Each robot foot's landmark target per frame, as contact_enforcement.h's source_feet takes them (NaN
// translation: missing or no foot task; NaN first rotation entry: position only).
std::vector<std::vector<Eigen::Isometry3d>> SourceFootPoses(const MotionData& motion, const std::vector<int>& foot_tasks) {
  std::vector<std::vector<Eigen::Isometry3d>> poses(foot_tasks.size());
  for (size_t f = 0; f < foot_tasks.size(); ++f) {
    poses[f].assign(static_cast<size_t>(motion.frames()), Eigen::Isometry3d::Identity());
    for (int64_t t = 0; t < motion.frames(); ++t) {
      Eigen::Isometry3d& pose = poses[f][static_cast<size_t>(t)];
      if (foot_tasks[f] < 0) {
        pose.translation().setConstant(std::nan(""));
      } else if (!StoredTarget(motion, t, foot_tasks[f], &pose)) {
        pose.linear()(0, 0) = std::nan("");
      }
    }
  }
  return poses;
}

// One foot's sole in a pose: the centre of its sole points and the lowest one's height.
FootSample SoleSample(const RobotFoot& foot, const Eigen::Isometry3d& pose) {
  FootSample sample;
  sample.lowest_z = std::numeric_limits<double>::infinity();
  for (const auto& point : foot.sole_points) {
    const Eigen::Vector3d world = pose * Eigen::Vector3d(point[0], point[1], point[2]);
    sample.x += world.x() / static_cast<double>(foot.sole_points.size());
    sample.y += world.y() / static_cast<double>(foot.sole_points.size());
    sample.lowest_z = std::min(sample.lowest_z, world.z());
  }
  return sample;
}

// GMD's foot-skating ratio (common/foot_sliding.h) of per-foot sole samples on the motion's frames.
double SkatingRatio(const std::vector<std::vector<FootSample>>& feet, const std::vector<double>& time_s) {
  if (feet.empty() || time_s.size() < 2) return 0.0;
  const double dt = (time_s.back() - time_s.front()) / static_cast<double>(time_s.size() - 1);
  FootSlidingOptions skating;
  skating.penetration = std::numeric_limits<double>::infinity();  // the skating measure alone
  const std::vector<uint8_t> flags = FindSlidingFrames(feet, dt, skating);
  return static_cast<double>(std::count(flags.begin(), flags.end(), 1)) / static_cast<double>(flags.size());
}

// Puts a motion on the floor its planted feet define: the whole motion and its targets move straight down
// by the median height of the lowest planted sole point over the source's contact frames. A vertical
// translation changes no joint angle, velocity or torque (no contact is modelled). Needed where the reference
// frame's heights are not the take's floor: a calibration frame is the converter's rest pose (CMU's T-poses
// stand some centimetres off it), and a source's own floor need not be where the robot's grounded stance
// puts it (Kimodo's G1 motions stand 3-4 cm below the map's soles). Contact enforcement lays planted soles on
// z = 0, so without this it would bend every stance leg by that offset.
void GroundOnPlantedSoles(const Model& model, Workspace& workspace, const RobotMap& map, const FootContacts& contacts,
                          MotionData& motion, std::vector<std::vector<IkTarget>>& frame_targets,
                          std::vector<std::string>& notes) {
  const int64_t nq = model.nq(), frames = motion.frames();
  std::vector<int> links;
  for (const RobotFoot& foot : map.feet) links.push_back(model.findLinkIndex(foot.link));
  const auto lowest_sole_of = [&](size_t f) { return SoleSample(map.feet[f], workspace.findLinkPose(links[f])).lowest_z; };
  std::vector<double> planted;
  planted.reserve(static_cast<size_t>(frames) * map.feet.size());
  Eigen::VectorXd q(nq);
  for (int64_t t = 0; t < frames; ++t) {
    bool any = false;
    for (size_t f = 0; f < map.feet.size(); ++f) any = any || contacts.at(t, static_cast<int>(f));
    if (!any) continue;
    q = Eigen::Map<const Eigen::VectorXd>(&motion.q[static_cast<size_t>(t * nq)], nq);
    workspace.setQ(q);
    for (size_t f = 0; f < map.feet.size(); ++f) {
      if (contacts.at(t, static_cast<int>(f))) planted.push_back(lowest_sole_of(f));
    }
  }
  if (planted.empty()) return;
  const double level = NearestRankPercentile(planted, 0.5);
  q = Eigen::Map<const Eigen::VectorXd>(motion.q.data(), nq);
  const int64_t vertical =
      VerticalCoordinate(model, q, [&](const Eigen::VectorXd& at) { return LowestSolePoint(model, workspace, map, at); });
  if (vertical < 0) return;
  for (int64_t t = 0; t < frames; ++t) motion.q[static_cast<size_t>(t * nq + vertical)] -= level;
  for (size_t i = 2; i < motion.landmark_targets.size(); i += 7) motion.landmark_targets[i] -= level;
  for (std::vector<IkTarget>& targets : frame_targets) {
    for (IkTarget& target : targets) target.position.z() -= level;
  }
  std::ostringstream note;
  note << "moved " << -1000 * level << " mm vertically, onto the planted soles";
  notes.push_back(note.str());
}

// What a user checks on the final motion, from the robot map's sole points: per source contact phase the
// sole centre's largest horizontal distance from where the phase began (drift); the deepest sole point and
// the share of frames with one more than 1 cm below the floor; GMD's foot-skating ratio of the robot beside
// the same measure on the source's foot targets (the capture scaled to the robot, with the robot's soles,
// heights from the level the source's planted frames sit at).
void MeasureContacts(const Model& model, Workspace& workspace, const RobotMap& map, const FootContacts& contacts,
                     const std::vector<int>& foot_tasks, const MotionData& motion, RetargetSummary& report) {
  const int64_t nq = model.nq(), frames = motion.frames();
  const size_t feet = map.feet.size();
  std::vector<int> links;
  for (const RobotFoot& foot : map.feet) links.push_back(model.findLinkIndex(foot.link));
  std::vector<std::vector<FootSample>> robot(feet), source(feet);
  for (size_t f = 0; f < feet; ++f) robot[f].reserve(static_cast<size_t>(frames)), source[f].reserve(static_cast<size_t>(frames));
  Eigen::VectorXd q(nq);
  int64_t penetrating = 0;
  for (int64_t t = 0; t < frames; ++t) {
    q = Eigen::Map<const Eigen::VectorXd>(&motion.q[static_cast<size_t>(t * nq)], nq);
    workspace.setQ(q);
    double lowest = std::numeric_limits<double>::infinity();
    for (size_t f = 0; f < feet; ++f) {
      robot[f].push_back(SoleSample(map.feet[f], workspace.findLinkPose(links[f])));
      lowest = std::min(lowest, robot[f].back().lowest_z);
      if (foot_tasks[f] < 0) continue;
      Eigen::Isometry3d pose;
      StoredTarget(motion, t, foot_tasks[f], &pose);
      const bool valid = pose.translation().allFinite();
      source[f].push_back(valid ? SoleSample(map.feet[f], pose) : source[f].empty() ? FootSample{} : source[f].back());
    }
    if (lowest < -0.01) ++penetrating;
    if (-lowest > report.deepest_penetration) report.deepest_penetration = -lowest, report.deepest_frame = t;
  }
  report.penetrating_fraction = frames ? static_cast<double>(penetrating) / static_cast<double>(frames) : 0.0;
  for (int f = 0; f < contacts.feet; ++f) report.contact_frames.push_back(contacts.framesInContact(f));
  report.contact_phases = contacts.phases;
  for (const ContactPhase& phase : contacts.phases) {
    const std::vector<FootSample>& sole = robot[static_cast<size_t>(phase.foot)];
    const FootSample& start = sole[static_cast<size_t>(phase.begin)];
    double drift = 0;
    for (int64_t t = phase.begin + 1; t < phase.end; ++t) {
      drift = std::max(drift, std::hypot(sole[static_cast<size_t>(t)].x - start.x, sole[static_cast<size_t>(t)].y - start.y));
    }
    report.phase_drift.push_back(drift);
  }
  if (!report.phase_drift.empty()) {
    report.median_drift = NearestRankPercentile(report.phase_drift, 0.5);
    report.p95_drift = NearestRankPercentile(report.phase_drift, 0.95);
    report.max_drift = *std::max_element(report.phase_drift.begin(), report.phase_drift.end());
  }
  report.foot_skating = SkatingRatio(robot, motion.time_s);
  std::vector<double> planted_levels;
  for (size_t f = 0; f < source.size(); ++f) {
    for (size_t t = 0; t < source[f].size(); ++t) {
      if (contacts.at(static_cast<int64_t>(t), static_cast<int>(f))) planted_levels.push_back(source[f][t].lowest_z);
    }
  }
  const double level = planted_levels.empty() ? 0.0 : NearestRankPercentile(planted_levels, 0.5);
  for (std::vector<FootSample>& foot : source) {
    for (FootSample& sample : foot) sample.lowest_z -= level;
  }
  source.erase(std::remove_if(source.begin(), source.end(), [](const auto& foot) { return foot.empty(); }), source.end());
  report.source_foot_skating = SkatingRatio(source, motion.time_s);
}

}  // namespace

const char* FloatingBaseChoiceName(FloatingBaseChoice choice) {
  switch (choice) {
    case FloatingBaseChoice::kFromMap: return "map";
    case FloatingBaseChoice::kAuto: return "auto";
    case FloatingBaseChoice::kFree: return "free";
    case FloatingBaseChoice::kFixed: return "fixed";
  }
  return "?";
}

bool ParseFloatingBaseChoice(const std::string& text, FloatingBaseChoice* choice) {
  for (FloatingBaseChoice candidate : {FloatingBaseChoice::kFromMap, FloatingBaseChoice::kAuto, FloatingBaseChoice::kFree,
                                       FloatingBaseChoice::kFixed}) {
    if (text == FloatingBaseChoiceName(candidate)) {
      *choice = candidate;
      return true;
    }
  }
  return false;
}

bool RetargetOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& message) {
    if (error) *error = message;
    return false;
  };
  if (model.empty()) return fail("--model is required (a URDF file)");
  if (robot_map.empty()) return fail("--robot-map is required (manifests/robots/NAME.toml)");
  if (markerset.empty()) return fail("--markerset is required (manifests/markersets/NAME.toml)");
  return HasValidValues(error);
}

bool RetargetOptions::HasValidValues(std::string* error) const {
  auto fail = [&](const std::string& message) {
    if (error) *error = message;
    return false;
  };
  if (!(smoothing >= 0)) return fail("--smoothing must be >= 0 (0: no trajectory refinement)");
  if (velocity_limit_scale && !(*velocity_limit_scale >= 0)) return fail("--velocity-limit-scale must be >= 0 (0: unbounded)");
  if (!(scale >= 0)) return fail("--scale must be auto or a positive number");
  if (max_bridge < 0) return fail("--max-bridge must be >= 0");
  if (!(posture_scale > 0)) return fail("--posture-scale must be > 0");
  if (!(ik_function_tolerance > 0 && ik_function_tolerance < 1)) return fail("--ik-function-tolerance must be in (0, 1)");
  if (max_roll && !(*max_roll >= 0 && *max_roll <= M_PI / 2)) return fail("--max-roll must be in [0, pi/2] rad");
  if (base_smoothing && !(*base_smoothing >= 0)) return fail("--base-smoothing must be >= 0 s");
  return contact.IsValid(error) && floor.IsValid(error) && enforcement.IsValid(error) && contact_forces.IsValid(error);
}

nlohmann::json RetargetOptions::ToJson() const {
  nlohmann::json scale_json = "auto";
  if (scale > 0) scale_json = scale;
  return {{"floating_base", FloatingBaseChoiceName(floating_base)}, {"reference_time", reference_time},
          {"scale", scale_json}, {"max_bridge", max_bridge}, {"velocity_limit_scale", velocity_limit_scale ? nlohmann::json(*velocity_limit_scale) : nlohmann::json("map")},
          {"smoothing", smoothing}, {"posture_scale", posture_scale}, {"ik_function_tolerance", ik_function_tolerance},
          {"contact_height", contact.height}, {"contact_speed", contact.speed}, {"contact_release", contact.release},
          {"contact_min_duration", contact.min_duration}, {"contact_uneven_ground", contact.uneven_ground},
          {"enforce_contacts", enforce_contacts}, {"flatten_terrain", flatten_terrain}, {"hold_foot_yaw", hold_foot_yaw},
          {"contact_blend", enforcement.blend}, {"contact_blend_horizontal", enforcement.horizontal_blend},
          {"stance_knee", enforcement.stance_knee},
          {"max_lowering", enforcement.max_lowering}, {"lowering_smoothing", enforcement.lowering_smoothing},
          {"max_roll", max_roll ? nlohmann::json(*max_roll) : nlohmann::json("map")}, {"contacts_above_speed", enforcement.contacts_above_speed},
          {"move_base_for_plants", enforcement.move_base_for_plants}, {"base_smoothing", base_smoothing ? nlohmann::json(*base_smoothing) : nlohmann::json("map")},
          {"heading_from_pelvis", heading_from_pelvis}, {"proportions", !proportions_per_chain ? "map" : *proportions_per_chain ? "chains" : "height"},
          {"friction", contact_forces.friction}, {"neutral_reference", neutral_reference},
          {"level_floor", floor.enabled}, {"level_floor_max_tilt_deg", floor.max_tilt * 180 / M_PI},
          {"level_floor_min_tilt_deg", floor.min_tilt * 180 / M_PI}};
}

std::string RetargetSummary::BriefReport() const {
  std::ostringstream out;
  out.precision(3);
  out << frames << " frames, reference " << (reference_frame < 0 ? std::string("the calibration frame") : "frame " + std::to_string(reference_frame)) << ", scale " << scale << " (arms " << arm_scale << "); median/p95 error "
      << "P1 " << median_position_error[0] * 1000 << "/" << p95_position_error[0] * 1000 << " mm "
      << median_angle_error[0] * 180 / M_PI << "/" << p95_angle_error[0] * 180 / M_PI << " deg, "
      << "P2 " << median_position_error[1] * 1000 << "/" << p95_position_error[1] * 1000 << " mm "
      << median_angle_error[1] * 180 / M_PI << "/" << p95_angle_error[1] * 180 / M_PI << " deg; worst joint step "
      << worst_joint_step << " rad (" << worst_joint_step_name << "); floor tilted " << floor_tilt_rad * 180 / M_PI << " deg"
      << (floor_levelled ? " (levelled)" : " (not levelled)") << "; IK " << ik_seconds << " s, " << mean_ik_iterations << " iterations/frame; refinement " << refinement_seconds << " s";
  if (!foot_sides.empty()) {
    out << "; source contact frames";
    for (size_t f = 0; f < foot_sides.size() && f < contact_frames.size(); ++f) out << " " << foot_sides[f] << " " << contact_frames[f];
    out << ", " << contact_phases.size() << " phases, stance drift median/p95/max " << median_drift * 1000 << "/"
        << p95_drift * 1000 << "/" << max_drift * 1000 << " mm; deepest sole point " << deepest_penetration * 1000
        << " mm below the floor, " << penetrating_fraction * 100 << " % of frames more than 1 cm below; foot skating "
        << foot_skating << " (source " << source_foot_skating << ")";
    if (contacts_enforced) {
      out << "; contacts enforced: " << enforcement.solved_frames << " frames' legs re-solved ("
          << enforcement.mean_iterations << " iterations), base lowered up to " << enforcement.max_lowering * 1000
          << " mm (" << enforcement.lowered_frames << " frames), pelvis moved for a plant in "
          << enforcement.base_moved_frames << " frames (up to " << enforcement.max_base_turn * 180 / M_PI << " deg, "
          << enforcement.max_base_shift * 1000 << " mm) and to hold plants within the legs' reach and speed in "
          << enforcement.speed_base_moved_frames << " frames, " << enforcement.moved_plants
          << " plants where the foot touched down off the plan, " << enforcement.unreachable_frames
          << " frames with a planted foot out of reach (more than 5 mm off its plant; " << enforcement.capped_lowering_frames
          << " foot-frames needed the base lowered past its cap), worst foot error " << enforcement.worst_position_error * 1000 << " mm / "
          << enforcement.worst_angle_error * 180 / M_PI << " deg, " << enforcement.rolled_foot_frames
          << " foot-frames rolled onto a sole edge, " << enforcement.lifted_frames
          << " frames with a foot lifted onto its lowest point (" << enforcement.raised_frames << " with the base), "
          << enforcement.lowered_onto_plant_frames << " frames with the base lowered onto a planted foot left in the air (up to "
          << enforcement.max_lowering_onto_plant * 1000 << " mm), "
          << enforcement.clearance_frames << " frames with a swing foot raised to the source's clearance, "
          << enforcement.overspeed_joint_frames << " leg joint-frames over their URDF velocity limit";
      if (enforcement.worst_speed_frame >= 0) {
        out << " (worst " << enforcement.worst_speed_ratio << "x, " << enforcement.worst_speed_joint << " at "
            << std::to_string(enforcement.worst_speed_time) << " s)";
      }
      out << ", planted legs with a joint on its limit in " << enforcement.limited_stance_frames << " of "
          << enforcement.planted_foot_frames << " planted foot-frames";
      if (!enforcement.most_limited_joint.empty()) {
        out << " (most " << enforcement.most_limited_joint << ", " << enforcement.most_limited_joint_frames << ")";
      }
    }
  }
  if (forces_split) {
    out << "; base residual mean " << mean_residual_force << " N / " << mean_residual_moment
        << " N·m, unexplained by contact forces " << mean_unexplained_force << " N / " << mean_unexplained_moment << " N·m";
  }
  return out.str();
}

RetargetInputs LoadRetargetInputs(const std::string& markers_path, const RetargetOptions& options) {
  RobotMap map = LoadRobotMap(options.robot_map);
  ModelOptions model_options;
  model_options.floating_base = FloatingBaseFromName(
      options.floating_base == FloatingBaseChoice::kFromMap ? map.floating_base : FloatingBaseChoiceName(options.floating_base));
  model_options.joint_ranges = map.joint_ranges;
  Model model = Model::Load(options.model, model_options);
  const auto joint_names = model.coordinateNames();
  CheckRobotMapNames(
      map, [&](const std::string& name) { return model.findLinkIndex(name) >= 0; },
      [&](const std::string& name) {
        return std::find(joint_names.begin(), joint_names.end(), name) != joint_names.end();
      },
      options.model);
  return RetargetInputs{markers_path, ReadMarkersFile(markers_path), LoadMarkerSet(options.markerset), std::move(map),
                        std::move(model)};
}

MotionData Retarget(const RetargetInputs& inputs, Workspace& workspace, const RetargetOptions& options,
                    RetargetSummary* summary) {
  RetargetSummary local_summary;
  RetargetSummary& report = summary ? *summary : local_summary;
  const Model& model = inputs.model;
  report.notes.insert(report.notes.end(), model.warnings().begin(), model.warnings().end());
  report.notes.insert(report.notes.end(), model.notes().begin(), model.notes().end());

  LandmarkTrajectories landmarks = ComputeLandmarks(inputs.capture, inputs.marker_set, inputs.capture_path);
  const int64_t frames = landmarks.frames;
  if (frames == 0) throw DataError(Location::InFile(inputs.capture_path), "the capture has no frames");
  const FloorPlane floor = EstimateFloorPlane(FootPositions(inputs.map, landmarks, nullptr), inputs.capture.time_s, options.floor);
  LevelLandmarks(floor, landmarks);
  report.floor_tilt_rad = floor.tilt_rad;
  report.floor_levelled = floor.levelled;
  if (floor.levelled) report.floor_rotation = floor.rotation;
  if (!floor.note.empty()) report.notes.push_back(floor.note);
  // The source's contacts, from the levelled take (before any terrain is flattened: what the subject stood on).
  const FootContacts contacts =
      inputs.map.feet.empty() ? FootContacts{} : SourceContacts(inputs.map, landmarks, inputs.capture.time_s, options, report.notes);
  if (floor.uneven && options.flatten_terrain && !inputs.map.feet.empty()) {
    const std::string note = TerrainFlatteningNote(
        FlattenTerrain(contacts, FootLandmarks(inputs.map, landmarks), options.contact.height, landmarks));
    if (!note.empty()) report.notes.push_back(note);
  }
  const TrackedTasks tasks = SelectTasks(inputs, landmarks, options, report.notes);
  // The landmarks at the reference stance: the capture's calibration frame, or a frame of the take.
  LandmarkTrajectories calibration = CalibrationLandmarks(inputs, tasks, options, report.notes);
  const bool calibrated = calibration.frames > 0;
  const int64_t take_reference = FindReferenceFrame(inputs, landmarks, tasks, options);
  if (calibrated) TurnCalibrationToTake(landmarks, take_reference, calibration);
  const LandmarkTrajectories& stance_landmarks = calibrated ? calibration : landmarks;
  const int64_t reference = calibrated ? 0 : take_reference;
  report.reference_frame = calibrated ? -1 : reference;

  // q_ref: the robot in the pose the landmarks are measured from; the posture target is the map's
  // reference stance either way.
  const Eigen::VectorXd q_posture = GroundedStance(model, workspace, inputs.map, inputs.map.reference_stance);
  const Eigen::VectorXd q_ref =
      calibrated ? GroundedStance(model, workspace, inputs.map, *inputs.map.calibration_stance) : q_posture;
  workspace.setQ(q_ref);
  std::vector<Eigen::Isometry3d> link_reference;
  for (const IkTask& task : tasks.ik) link_reference.push_back(workspace.findLinkPose(task.link));
  RobotStance robot_stance;
  robot_stance.link_reference = link_reference;
  std::vector<std::string> task_links;
  for (size_t i = 0; i < tasks.size(); ++i) {
    robot_stance.task_landmarks.push_back(landmarks.names[static_cast<size_t>(tasks.landmark[i])]);
    task_links.push_back(model.linkNames()[static_cast<size_t>(tasks.ik[i].link)]);
  }
  const bool per_chain = options.proportions_per_chain.value_or(inputs.map.proportions == "chains");
  if (per_chain && options.scale <= 0) {
    MeasureRobotLegs(model, workspace, task_links, robot_stance);
    MeasureRobotArms(model, workspace, task_links, robot_stance);
  }
  AlignmentOptions alignment_options;
  alignment_options.fixed_scale = options.scale;
  alignment_options.per_chain = per_chain;
  alignment_options.heading_from_pelvis = options.heading_from_pelvis && options.reference_time < 0;
  // Heights from the capture's calibration frame (a BVH's T-pose: standing straight) where the take's first
  // frame is the reference: a dance's first frame may be a crouch (CMU 94_15: scale 0.668 from it, 0.537
  // standing), and the G1 then moved 24 % more than the dancer's proportions ask.
  const bool measure_standing = !calibrated && options.reference_time < 0 && options.scale <= 0;
  const LandmarkTrajectories standing = measure_standing ? CalibrationFrameLandmarks(inputs) : LandmarkTrajectories{};
  if (standing.frames > 0) alignment_options.stature = &standing;
  const StanceAlignment alignment = AlignToRobot(stance_landmarks, robot_stance, reference, alignment_options, report.notes);
  report.heading_rad = alignment.heading_rad;
  report.scale = alignment.leg_scale;
  report.arm_scale = alignment.arm_scale;

  // Per robot-map foot, the task tracking it (-1: none).
  const std::vector<int> foot_tasks = FootTasks(inputs.map, model, landmarks, tasks);
  std::vector<LandmarkSample> reference_samples;
  if (options.neutral_reference && !calibrated && options.reference_time < 0) {
    std::vector<bool> feet(tasks.size(), false);
    for (int task : foot_tasks) {
      if (task >= 0) feet[static_cast<size_t>(task)] = true;
    }
    reference_samples = NeutralReference(landmarks, reference, tasks.landmark, feet);
  } else {
    for (int64_t landmark : tasks.landmark) reference_samples.push_back(SampleAt(stance_landmarks, reference, landmark));
  }
  const RobotMap& map = inputs.map;
  const double velocity_limit_scale = options.velocity_limit_scale.value_or(map.velocity_limit_scale);
  const double posture_weight =
      map.priority_weights[static_cast<size_t>(map.posture_priority - 1)] * map.posture_weight * options.posture_scale;
  FrameIkOptions ik_options;
  ik_options.function_tolerance = options.ik_function_tolerance;
  ik_options.velocity_limit_scale = velocity_limit_scale;
  FrameIk ik(model, tasks.ik, q_posture, posture_weight, ik_options);

  MotionData motion = EmptyMotion(model, inputs.capture, landmarks, tasks);
  std::vector<int64_t> bridged;
  std::vector<std::vector<IkTarget>> frame_targets(static_cast<size_t>(frames));
  const auto start = std::chrono::steady_clock::now();
  // The take starts from the posture stance: nearer its first frame than a calibration T-pose is. Its knees
  // start bent: from a straight leg (a straight reference stance) the solver cannot tell which way to bend,
  // and a scaled human's foot targets, often just beyond reach, then leave it straight with the base high,
  // from where the next frames bend it only as fast as the motors allow.
  Eigen::VectorXd q_start = q_posture;
  BendBranchJoints(BranchCoordinates(model), q_start);
  FootYawHolds holds = options.hold_foot_yaw
                           ? PlanFootYawHolds(model, workspace, tasks, foot_tasks, landmarks, q_ref, link_reference)
                           : FootYawHolds{};
  SolveFrames(landmarks, tasks, reference_samples, link_reference, alignment, q_start, velocity_limit_scale, holds, ik,
              motion, frame_targets, bridged, report);
  if (holds.held_foot_frames > 0) {
    report.notes.push_back(std::to_string(holds.held_foot_frames) +
                           " foot-frame(s) whose source foot turned about the pelvis further than the leg's joints can turn "
                           "it: their orientation targets held at the leg's limit (foot_yaw_range.h)");
  }
  report.ik_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  BridgeGaps(model, motion.time_s, bridged, options.max_bridge, inputs.capture_path, motion.q);

  const auto refine_start = std::chrono::steady_clock::now();
  RefinementOptions refinement;
  refinement.smoothing = options.smoothing;
  refinement.velocity_limit_scale = velocity_limit_scale;
  RefineTrajectory(ik, model, frame_targets, motion.time_s, motion.q, refinement);
  report.refinement_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - refine_start).count();

  if ((calibrated || options.enforce_contacts) && !map.feet.empty()) {
    GroundOnPlantedSoles(model, workspace, map, contacts, motion, frame_targets, report.notes);
  }
  if (options.enforce_contacts && !map.feet.empty()) {
    const Eigen::VectorXd q_first = Eigen::Map<const Eigen::VectorXd>(motion.q.data(), model.nq());
    const int64_t vertical = VerticalCoordinate(
        model, q_first, [&](const Eigen::VectorXd& at) { return LowestSolePoint(model, workspace, map, at); });
    const auto enforce_start = std::chrono::steady_clock::now();
    ContactEnforcementOptions enforcement = options.enforcement;
    enforcement.velocity_limit_scale = velocity_limit_scale;
    enforcement.max_roll = options.max_roll.value_or(map.max_roll);
    enforcement.base_smoothing = options.base_smoothing.value_or(map.base_smoothing);
    EnforceContacts(model, workspace, map.feet, contacts, SourceFootPoses(motion, foot_tasks),
                    vertical, motion.time_s, map.file, enforcement, motion.q, &report.enforcement);
    report.refinement_seconds += std::chrono::duration<double>(std::chrono::steady_clock::now() - enforce_start).count();
    report.contacts_enforced = true;
  }
  MeasureLandmarkErrors(ik, tasks, frame_targets, model.nq(), motion, report);
  if (!map.feet.empty()) {
    for (const RobotFoot& foot : map.feet) motion.contact_feet.push_back(foot.side), report.foot_sides.push_back(foot.side);
    motion.contact.assign(contacts.contact.begin(), contacts.contact.end());
    MeasureContacts(model, workspace, map, contacts, foot_tasks, motion, report);
  }
  ComputeDynamics(model, workspace, map, options.contact_forces, motion, report);
  FindWorstJointStep(model, motion, report);
  report.frames = frames;
  return motion;
}

MotionData RetargetFile(const std::string& markers_path, const RetargetOptions& options, RetargetSummary* summary) {
  const RetargetInputs inputs = LoadRetargetInputs(markers_path, options);
  Workspace workspace(inputs.model);
  return Retarget(inputs, workspace, options, summary);
}

}  // namespace syn
