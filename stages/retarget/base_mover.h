// Moving a robot's floating base by a pose correction, whichever way the model parametrises it.
//
// Contact enforcement moves the pelvis where a planted leg cannot hold its plant (contact_enforcement.h).
// A free base (quaternion and position) moves by integrating the correction; a virtual base chain written
// into the URDF (HRP-4C: prismatic x, y, z then revolute x, y, z through massless links, every joint frame
// at its parent's origin) by re-reading its six coordinates from the moved pose: the position, and the
// rotation's x-y-z angles nearest the ones it had. Other parametrisations are not moved (canMove false).
#pragma once

#include <array>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "common/model.h"

namespace syn {

class BaseMover {
 public:
  explicit BaseMover(const Model& model);

  bool canMove() const { return link_ >= 0; }
  // The link the base carries (the pelvis), -1 when canMove is false.
  int link() const { return link_; }
  // q's base moved by `correction`: rotation vector (first three) and translation, both in the ground
  // frame, R = exp(ω) R0 and p = p0 + v for the base link's pose. Allocates nothing.
  void apply(const Eigen::Matrix<double, 6, 1>& correction, Eigen::VectorXd& q) const;

 private:
  bool free_ = false;
  int link_ = -1;
  std::array<int, 6> virtual_q_{};  // q indices of the virtual chain's x, y, z prismatic and x, y, z revolute joints
};

}  // namespace syn
