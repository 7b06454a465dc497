// The Simbody side of Model, shared by the translation units in common/simbody/
// that need the multibody system itself (Workspace, the Assembler comparison).
// Not for stages: they use common/model.h.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>
#include <Simbody.h>

#include "common/model.h"

namespace syn {

inline SimTK::Rotation ToSimbodyRotation(const Eigen::Matrix3d& r) {
  return SimTK::Rotation(SimTK::Mat33(r(0, 0), r(0, 1), r(0, 2), r(1, 0), r(1, 1), r(1, 2), r(2, 0), r(2, 1), r(2, 2)), true);
}

inline SimTK::Transform ToSimbody(const Eigen::Isometry3d& pose) {
  const Eigen::Matrix3d& r = pose.linear();
  const SimTK::Mat33 rotation(r(0, 0), r(0, 1), r(0, 2), r(1, 0), r(1, 1), r(1, 2), r(2, 0), r(2, 1), r(2, 2));
  const Eigen::Vector3d& t = pose.translation();
  return SimTK::Transform(SimTK::Rotation(rotation, true), SimTK::Vec3(t.x(), t.y(), t.z()));
}

inline Eigen::Isometry3d ToEigen(const SimTK::Transform& transform) {
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  const SimTK::Mat33& r = transform.R().asMat33();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) pose.linear()(i, j) = r(i, j);
    pose.translation()[i] = transform.p()[i];
  }
  return pose;
}

// Where each URDF link lives in the Simbody system.
struct LinkPlacement {
  SimTK::MobilizedBodyIndex body;
  Eigen::Isometry3d in_body = Eigen::Isometry3d::Identity();  // link frame in the body frame
};

struct Model::Impl {
  SimTK::MultibodySystem system;
  SimTK::SimbodyMatterSubsystem matter{system};
  SimTK::GeneralForceSubsystem forces{system};
  SimTK::Force::Gravity gravity_force;

  std::string name, path, sha256;
  FloatingBase floating_base = FloatingBase::kFree;
  double gravity = 9.80665;
  double total_mass = 0.0;
  int nq = 0, nu = 0;
  std::vector<std::string> coordinate_names, velocity_names, link_names;
  std::vector<LinkPlacement> links;
  std::vector<std::string> warnings;
  std::vector<std::string> notes;
  std::vector<ModelJoint> joints;
  Eigen::VectorXd q_lower, q_upper, u_limit, effort_limit;
  std::vector<bool> actuated;  // [nu]

  // How each mobilized body moves, for the analytic frame Jacobian: a joint
  // axis through the body origin (the child link frame coincides with the
  // URDF joint frame), or the free base's six velocities.
  enum class MobilityKind { kGround, kFree, kPin, kSlider };
  struct Mobility {
    MobilityKind kind = MobilityKind::kGround;
    int u_index = -1;
    int parent = -1;                                     // mobilized body index
    Eigen::Vector3d axis_in_body = Eigen::Vector3d::UnitZ();
  };
  std::vector<Mobility> mobilities;  // by mobilized body index

  explicit Impl(double g) : gravity_force(forces, matter, -SimTK::ZAxis, g), gravity(g) {}
};

}  // namespace syn
