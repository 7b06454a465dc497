// Forward kinematics of a Model's whole link tree, and a link's frame Jacobian, from the URDF joint frames
// alone: a product of one transform per joint instead of realising a Simbody state.
//
// Why: the retargeter's per-frame IK evaluates its cost and Jacobian at every Levenberg–Marquardt
// iteration, and Debian's Simbody runs its consistency checks on every Workspace::setQ — a fifth of the
// whole stage's time on CMU dances (perf, 08_07). The conventions are the Workspace's (model.h): a free
// base's q is (quaternion w, x, y, z, position), its u (angular velocity, linear velocity of the base
// origin), both in the ground frame; a link's frame is its URDF joint frame moved by the joint. Tests
// compare every link pose and Jacobian with the Workspace's.
#pragma once

#include <vector>

#include <Eigen/Geometry>

#include "common/model.h"

namespace syn {

class TreeKinematics {
 public:
  explicit TreeKinematics(const Model& model);

  // Every link's pose at q (nq; a free base's quaternion is normalised, as Workspace::setQ does).
  void setQ(const Eigen::VectorXd& q);
  // Link `link`'s pose (ground frame) at the last setQ.
  const Eigen::Isometry3d& linkPose(int link) const { return pose_[static_cast<size_t>(link)]; }
  // The 6 × nu Jacobian of link `link`'s origin at the last setQ, rows (angular velocity, linear velocity)
  // in the ground frame, as Workspace::calcFrameJacobian at the origin. `jacobian` must be 6 × nu.
  void frameJacobian(int link, Eigen::Matrix<double, 6, Eigen::Dynamic>& jacobian) const;

 private:
  enum class Motion { kFixed, kRevolute, kPrismatic, kFree };
  // One joint, in an order where each parent link's pose is known before its children's.
  struct Step {
    Motion motion = Motion::kFixed;
    int parent = -1;  // link index; -1: the ground
    int child = -1;
    int q = -1, u = -1;
    Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();
    Eigen::Vector3d axis = Eigen::Vector3d::UnitX();
  };
  std::vector<Step> steps_;
  std::vector<int> step_of_link_;          // the step that moves each link (-1: none, welded to the ground)
  std::vector<Eigen::Isometry3d> pose_;    // per link
  std::vector<Eigen::Vector3d> axis_;      // per step: its axis in the ground frame at the last setQ
};

}  // namespace syn
