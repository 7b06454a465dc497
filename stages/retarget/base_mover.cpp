#include "stages/retarget/base_mover.h"

#include <algorithm>
#include <cmath>
#include <string>

#include "common/configuration_space.h"

namespace syn {
namespace {

// `angles` with each shifted by whole turns to within π of `near`.
Eigen::Vector3d NearestTurns(Eigen::Vector3d angles, const Eigen::Vector3d& near) {
  for (int i = 0; i < 3; ++i) angles[i] += 2 * M_PI * std::round((near[i] - angles[i]) / (2 * M_PI));
  return angles;
}

// The x-y-z angles (R = Rx(a) Ry(b) Rz(c)) of `rotation` nearest `near`. Every rotation has two such triples,
// (a, b, c) and (a + π, π − b, c + π), each up to whole turns: the nearer one over all three angles. With
// only the first, a pelvis pitched near ±90° (CMU 94_07's deep squat onto HRP-4C) had a and c picked a turn
// apart from one frame to the next, 2π steps in its virtual base's coordinates.
Eigen::Vector3d XyzAngles(const Eigen::Matrix3d& rotation, const Eigen::Vector3d& near) {
  const double b = std::asin(std::clamp(rotation(0, 2), -1.0, 1.0));
  const Eigen::Vector3d first(std::atan2(-rotation(1, 2), rotation(2, 2)), b, std::atan2(-rotation(0, 1), rotation(0, 0)));
  const Eigen::Vector3d one = NearestTurns(first, near);
  const Eigen::Vector3d other = NearestTurns(first + Eigen::Vector3d(M_PI, M_PI - 2 * b, M_PI), near);
  return (other - near).squaredNorm() < (one - near).squaredNorm() ? other : one;
}

}  // namespace

BaseMover::BaseMover(const Model& model) {
  if (model.hasFreeBase()) {
    free_ = true;
    link_ = model.freeBaseLink();
    return;
  }
  // A virtual chain: the unactuated joints in file order, three prismatic along x, y, z then three revolute
  // about x, y, z, each frame at its parent's origin.
  const Eigen::Vector3d axes[3] = {Eigen::Vector3d::UnitX(), Eigen::Vector3d::UnitY(), Eigen::Vector3d::UnitZ()};
  int found = 0;
  std::string child;
  for (const ModelJoint& joint : model.joints()) {
    if (joint.u_index < 0 || model.actuatedVelocities()[static_cast<size_t>(joint.u_index)]) continue;
    if (found >= 6) return;
    const bool prismatic = found < 3;
    if (joint.type != (prismatic ? "prismatic" : "revolute") || !joint.origin.isApprox(Eigen::Isometry3d::Identity(), 1e-12) ||
        !joint.axis.isApprox(axes[found % 3], 1e-12) || (found > 0 && joint.parent != child)) {
      return;
    }
    virtual_q_[static_cast<size_t>(found++)] = joint.q_index;
    child = joint.child;
  }
  if (found == 6) link_ = model.findLinkIndex(child);
}

void BaseMover::apply(const Eigen::Matrix<double, 6, 1>& correction, Eigen::VectorXd& q) const {
  if (link_ < 0) return;
  if (free_) {
    // The free joint's velocity is (ω, v) in the ground frame: integrating it for unit time is the move.
    Eigen::Matrix<double, 7, 1> from = q.head<7>(), to;
    Integrate(ConfigurationShape::Of(true, 7), from.data(), correction.data(), to.data());
    q.head<7>() = to;
    return;
  }
  Eigen::Vector3d position, angles;
  for (int i = 0; i < 3; ++i) position[i] = q[virtual_q_[static_cast<size_t>(i)]], angles[i] = q[virtual_q_[static_cast<size_t>(i + 3)]];
  const Eigen::Matrix3d rotation = (Eigen::AngleAxisd(angles[0], Eigen::Vector3d::UnitX()) *
                                    Eigen::AngleAxisd(angles[1], Eigen::Vector3d::UnitY()) *
                                    Eigen::AngleAxisd(angles[2], Eigen::Vector3d::UnitZ())).toRotationMatrix();
  const Eigen::Vector3d omega = correction.head<3>();
  const double turn = omega.norm();
  const Eigen::Matrix3d moved = turn > 0 ? Eigen::Matrix3d(Eigen::AngleAxisd(turn, omega / turn) * rotation) : rotation;
  position += correction.tail<3>();
  angles = XyzAngles(moved, angles);
  for (int i = 0; i < 3; ++i) q[virtual_q_[static_cast<size_t>(i)]] = position[i], q[virtual_q_[static_cast<size_t>(i + 3)]] = angles[i];
}

}  // namespace syn
