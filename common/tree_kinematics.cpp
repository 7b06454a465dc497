#include "common/tree_kinematics.h"

#include <stdexcept>
#include <string>

namespace syn {

TreeKinematics::TreeKinematics(const Model& model) {
  const std::vector<std::string>& links = model.linkNames();
  const std::vector<ModelJoint>& joints = model.joints();
  step_of_link_.assign(links.size(), -1);
  pose_.assign(links.size(), Eigen::Isometry3d::Identity());
  std::vector<bool> placed(joints.size(), false), known(links.size(), false);
  // A link no joint moves is welded to the ground (a fixed base's root).
  for (size_t l = 0; l < links.size(); ++l) {
    bool child = false;
    for (const ModelJoint& joint : joints) child = child || joint.child == links[l];
    known[l] = !child;
  }
  // Joints in parent-before-child order: repeated passes, as a URDF lists its joints in any order.
  for (bool progress = true; progress;) {
    progress = false;
    for (size_t j = 0; j < joints.size(); ++j) {
      if (placed[j]) continue;
      const ModelJoint& joint = joints[j];
      const int parent = model.findLinkIndex(joint.parent), child = model.findLinkIndex(joint.child);
      if (child < 0 || (parent >= 0 && !known[static_cast<size_t>(parent)])) continue;
      Step step;
      step.parent = parent, step.child = child, step.q = joint.q_index, step.u = joint.u_index;
      step.origin = joint.origin;
      step.axis = joint.axis.normalized();
      if (joint.type == "revolute" || joint.type == "continuous") step.motion = Motion::kRevolute;
      else if (joint.type == "prismatic") step.motion = Motion::kPrismatic;
      else if (joint.type == "free") step.motion = Motion::kFree;
      else if (joint.type == "fixed") step.motion = Motion::kFixed;
      else throw std::invalid_argument("TreeKinematics: joint " + joint.name + " has type " + joint.type);
      step_of_link_[static_cast<size_t>(child)] = static_cast<int>(steps_.size());
      steps_.push_back(step);
      placed[j] = known[static_cast<size_t>(child)] = progress = true;
    }
  }
  for (size_t j = 0; j < joints.size(); ++j) {
    if (!placed[j]) throw std::invalid_argument("TreeKinematics: joint " + joints[j].name + " is not on the tree");
  }
  axis_.assign(steps_.size(), Eigen::Vector3d::Zero());
}

void TreeKinematics::setQ(const Eigen::VectorXd& q) {
  for (size_t s = 0; s < steps_.size(); ++s) {
    const Step& step = steps_[s];
    const Eigen::Isometry3d parent = step.parent >= 0 ? pose_[static_cast<size_t>(step.parent)] : Eigen::Isometry3d::Identity();
    Eigen::Isometry3d& pose = pose_[static_cast<size_t>(step.child)];
    switch (step.motion) {
      case Motion::kFixed:
        pose = parent * step.origin;
        break;
      case Motion::kRevolute:
        pose = parent * step.origin;
        axis_[s] = pose.linear() * step.axis;
        pose.linear() = pose.linear() * Eigen::AngleAxisd(q[step.q], step.axis).toRotationMatrix();
        break;
      case Motion::kPrismatic:
        pose = parent * step.origin;
        axis_[s] = pose.linear() * step.axis;
        pose.translation() += axis_[s] * q[step.q];
        break;
      case Motion::kFree: {
        const Eigen::Quaterniond turn(q[step.q], q[step.q + 1], q[step.q + 2], q[step.q + 3]);
        Eigen::Isometry3d moved = Eigen::Isometry3d::Identity();
        moved.linear() = turn.normalized().toRotationMatrix();
        moved.translation() = Eigen::Vector3d(q[step.q + 4], q[step.q + 5], q[step.q + 6]);
        pose = parent * step.origin * moved;
        break;
      }
    }
  }
}

void TreeKinematics::frameJacobian(int link, Eigen::Matrix<double, 6, Eigen::Dynamic>& jacobian) const {
  jacobian.setZero();
  const Eigen::Vector3d at = pose_[static_cast<size_t>(link)].translation();
  for (int s = step_of_link_[static_cast<size_t>(link)]; s >= 0;) {
    const Step& step = steps_[static_cast<size_t>(s)];
    const Eigen::Vector3d joint = pose_[static_cast<size_t>(step.child)].translation();
    switch (step.motion) {
      case Motion::kFixed:
        break;
      case Motion::kRevolute:
        jacobian.col(step.u) << axis_[static_cast<size_t>(s)], axis_[static_cast<size_t>(s)].cross(at - joint);
        break;
      case Motion::kPrismatic:
        jacobian.col(step.u).tail<3>() = axis_[static_cast<size_t>(s)];
        break;
      case Motion::kFree:
        for (int i = 0; i < 3; ++i) {
          const Eigen::Vector3d e = Eigen::Vector3d::Unit(i);
          jacobian.col(step.u + i) << e, e.cross(at - joint);
          jacobian.col(step.u + 3 + i).tail<3>() = e;
        }
        break;
    }
    s = step.parent >= 0 ? step_of_link_[static_cast<size_t>(step.parent)] : -1;
  }
}

}  // namespace syn
