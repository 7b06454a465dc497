#include "stages/export/robot_learning_export.h"

#include <cmath>
#include <cstdio>
#include <set>
#include <sstream>

#include <Eigen/Geometry>

#include "common/error.h"
#include "stages/export/npz_writer.h"

#include "stages/export/number_text.h"

namespace syn {
namespace {


void CheckModel(const MotionData& motion, const Model& model) {
  if (motion.coordinate_names != model.coordinateNames()) {
    throw DataError(Location::InFile(model.sourcePath()), "the motion's coordinates are not those of " + model.name());
  }
}

// The robot's joints that move, in URDF file order: (name, q index).
std::vector<std::pair<std::string, int>> RobotJoints(const Model& model) {
  std::vector<std::pair<std::string, int>> joints;
  for (const ModelJoint& joint : model.joints()) {
    if (joint.q_index >= 0 && joint.type != "free") joints.emplace_back(joint.name, joint.q_index);
  }
  return joints;
}

// Frames per second of a uniformly sampled motion; DataError otherwise.
double UniformRate(const MotionData& motion) {
  if (motion.frames() < 2) {
    throw DataError(Location::InFile("motion"), "needs at least 2 frames for a frame rate");
  }
  const double span = motion.time_s.back() - motion.time_s.front();
  const double step = span / static_cast<double>(motion.frames() - 1);
  for (size_t t = 1; t < motion.time_s.size(); ++t) {
    if (std::abs(motion.time_s[t] - motion.time_s[t - 1] - step) > 1e-6 * step + 1e-9) {
      throw DataError(Location::AtFrame("motion", static_cast<int64_t>(t)),
                      "frames are not evenly spaced in time; resample with --rate HZ");
    }
  }
  return 1.0 / step;
}

// Every URDF link's world pose per frame, by forward kinematics: poses[t * links + l].
std::vector<Eigen::Isometry3d> LinkPoses(const MotionData& motion, const Model& model) {
  Workspace workspace(model);
  const size_t links = model.linkNames().size();
  std::vector<Eigen::Isometry3d> poses(static_cast<size_t>(motion.frames()) * links);
  Eigen::VectorXd q(model.nq());
  for (int64_t t = 0; t < motion.frames(); ++t) {
    q = Eigen::Map<const Eigen::VectorXd>(&motion.q[static_cast<size_t>(t * motion.nq())], motion.nq());
    workspace.setQ(q);
    for (size_t l = 0; l < links; ++l) poses[static_cast<size_t>(t) * links + l] = workspace.findLinkPose(static_cast<int>(l));
  }
  return poses;
}

// The URDF root link: no joint's child.
int RootLink(const Model& model) {
  std::set<std::string> children;
  for (const ModelJoint& joint : model.joints()) {
    if (joint.type != "free") children.insert(joint.child);
  }
  for (size_t l = 0; l < model.linkNames().size(); ++l) {
    if (!children.count(model.linkNames()[l])) return static_cast<int>(l);
  }
  return 0;
}

// Unit quaternion of a rotation, sign chosen continuous with `previous` (a quaternion and its
// negative are one rotation; consumers interpolate).
Eigen::Quaterniond ContinuousQuaternion(const Eigen::Matrix3d& rotation, const Eigen::Quaterniond* previous) {
  Eigen::Quaterniond quaternion(rotation);
  quaternion.normalize();
  if (previous && quaternion.dot(*previous) < 0) quaternion.coeffs() *= -1.0;
  return quaternion;
}

// Central-difference neighbours of frame t (one-sided at the ends).
std::pair<size_t, size_t> Neighbours(size_t t, size_t frames) {
  return {t == 0 ? 0 : t - 1, t + 1 == frames ? t : t + 1};
}

}  // namespace

std::string MotionToUnitreeCsv(const MotionData& motion, const Model& model) {
  CheckModel(motion, model);
  if (!model.hasFreeBase()) {
    throw DataError(Location::InFile(model.sourcePath()), "the Unitree CSV layout needs a free-floating base");
  }
  const auto joints = RobotJoints(model);
  std::ostringstream text;
  for (int64_t t = 0; t < motion.frames(); ++t) {
    const double* q = &motion.q[static_cast<size_t>(t * motion.nq())];  // base: qw qx qy qz x y z
    // Root position, then the quaternion scalar last (q holds w, x, y, z at 0..3, the position at 4..6).
    for (int index : {4, 5, 6, 1, 2, 3}) text << ShortestNumberText(q[index]) << ',';
    text << ShortestNumberText(q[0]);
    for (const auto& joint : joints) text << ',' << ShortestNumberText(q[joint.second]);
    text << '\n';
  }
  return text.str();
}

std::string MotionToGmrNpz(const MotionData& motion, const Model& model) {
  CheckModel(motion, model);
  const double fps = UniformRate(motion);
  const auto joints = RobotJoints(model);
  const std::vector<Eigen::Isometry3d> poses = LinkPoses(motion, model);
  const size_t frames = static_cast<size_t>(motion.frames()), links = model.linkNames().size();
  const size_t root = static_cast<size_t>(RootLink(model));
  NpyArray root_pos = NpyArray::Numbers("root_pos", {motion.frames(), 3});
  NpyArray root_rot = NpyArray::Numbers("root_rot", {motion.frames(), 4});
  NpyArray dof_pos = NpyArray::Numbers("dof_pos", {motion.frames(), static_cast<int64_t>(joints.size())});
  NpyArray local_body_pos = NpyArray::Numbers("local_body_pos", {motion.frames(), static_cast<int64_t>(links), 3});
  Eigen::Quaterniond previous;
  for (size_t t = 0; t < frames; ++t) {
    const Eigen::Isometry3d& root_pose = poses[t * links + root];
    const Eigen::Quaterniond rotation = ContinuousQuaternion(root_pose.linear(), t ? &previous : nullptr);
    previous = rotation;
    root_pos.values.insert(root_pos.values.end(), {root_pose.translation().x(), root_pose.translation().y(), root_pose.translation().z()});
    root_rot.values.insert(root_rot.values.end(), {rotation.x(), rotation.y(), rotation.z(), rotation.w()});
    for (const auto& joint : joints) dof_pos.values.push_back(motion.q[t * static_cast<size_t>(motion.nq()) + static_cast<size_t>(joint.second)]);
    for (size_t l = 0; l < links; ++l) {
      const Eigen::Vector3d local = root_pose.linear().transpose() * (poses[t * links + l].translation() - root_pose.translation());
      local_body_pos.values.insert(local_body_pos.values.end(), {local.x(), local.y(), local.z()});
    }
  }
  NpyArray joint_names = NpyArray::Text("joint_names", {});
  for (const auto& joint : joints) joint_names.strings.push_back(joint.first);
  return NpzBytes({NpyArray::Numbers("fps", {}, {fps}), root_pos, root_rot, dof_pos, local_body_pos,
                   NpyArray::Text("link_body_list", model.linkNames()), joint_names});
}

std::string MotionToMjlabNpz(const MotionData& motion, const Model& model) {
  CheckModel(motion, model);
  const double fps = UniformRate(motion);
  const auto joints = RobotJoints(model);
  const std::vector<Eigen::Isometry3d> poses = LinkPoses(motion, model);
  const size_t frames = static_cast<size_t>(motion.frames()), links = model.linkNames().size();
  const int64_t T = motion.frames(), J = static_cast<int64_t>(joints.size()), B = static_cast<int64_t>(links);
  NpyArray joint_pos = NpyArray::Numbers("joint_pos", {T, J}), joint_vel = NpyArray::Numbers("joint_vel", {T, J});
  NpyArray body_pos = NpyArray::Numbers("body_pos_w", {T, B, 3}), body_quat = NpyArray::Numbers("body_quat_w", {T, B, 4});
  NpyArray body_lin_vel = NpyArray::Numbers("body_lin_vel_w", {T, B, 3});
  NpyArray body_ang_vel = NpyArray::Numbers("body_ang_vel_w", {T, B, 3});
  const auto q_at = [&](size_t t, int index) { return motion.q[t * static_cast<size_t>(motion.nq()) + static_cast<size_t>(index)]; };
  std::vector<Eigen::Quaterniond> previous(links);
  for (size_t t = 0; t < frames; ++t) {
    const auto [before, after] = Neighbours(t, frames);
    const double dt = motion.time_s[after] - motion.time_s[before];
    for (const auto& joint : joints) {
      joint_pos.values.push_back(q_at(t, joint.second));
      joint_vel.values.push_back((q_at(after, joint.second) - q_at(before, joint.second)) / dt);
    }
    for (size_t l = 0; l < links; ++l) {
      const Eigen::Isometry3d& pose = poses[t * links + l];
      const Eigen::Quaterniond rotation = ContinuousQuaternion(pose.linear(), t ? &previous[l] : nullptr);
      previous[l] = rotation;
      body_pos.values.insert(body_pos.values.end(), {pose.translation().x(), pose.translation().y(), pose.translation().z()});
      body_quat.values.insert(body_quat.values.end(), {rotation.w(), rotation.x(), rotation.y(), rotation.z()});
      const Eigen::Vector3d velocity = (poses[after * links + l].translation() - poses[before * links + l].translation()) / dt;
      const Eigen::AngleAxisd turn(poses[after * links + l].linear() * poses[before * links + l].linear().transpose());
      const Eigen::Vector3d angular = turn.axis() * turn.angle() / dt;
      body_lin_vel.values.insert(body_lin_vel.values.end(), {velocity.x(), velocity.y(), velocity.z()});
      body_ang_vel.values.insert(body_ang_vel.values.end(), {angular.x(), angular.y(), angular.z()});
    }
  }
  NpyArray joint_names = NpyArray::Text("joint_names", {});
  for (const auto& joint : joints) joint_names.strings.push_back(joint.first);
  return NpzBytes({NpyArray::Numbers("fps", {1}, {fps}), joint_pos, joint_vel, body_pos, body_quat, body_lin_vel,
                   body_ang_vel, joint_names, NpyArray::Text("body_names", model.linkNames())});
}

}  // namespace syn
