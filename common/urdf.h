// URDF robot descriptions as plain data (no Simbody), read with tinyxml2.
//
// Only what dynamics and kinematics need is kept: links with their inertial
// properties, joints with origin, axis and limits. Visual, collision,
// transmission and gazebo elements are ignored (meshes need not exist), and
// so are XML comments (HRP-4C's `floating` joint lives inside one).
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace syn {

enum class UrdfJointType { kRevolute, kContinuous, kPrismatic, kFixed, kFloating };

struct UrdfInertial {
  double mass = 0.0;                                         // kg
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();  // inertial frame in the link frame
  Eigen::Matrix3d inertia = Eigen::Matrix3d::Zero();         // about the COM, in the inertial frame (kg m²)
};

struct UrdfLink {
  std::string name;
  UrdfInertial inertial;
  int line = 0;
};

struct UrdfJoint {
  std::string name;
  UrdfJointType type = UrdfJointType::kFixed;
  std::string parent, child;
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();  // child joint frame in the parent link frame
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();           // unit, in the joint frame
  bool has_limits = false;
  double lower = 0.0, upper = 0.0, velocity = 0.0, effort = 0.0;
  int line = 0;
};

struct RobotDescription {
  std::string name;
  std::string file;
  std::vector<UrdfLink> links;    // file order
  std::vector<UrdfJoint> joints;  // file order
  int root_link = -1;             // the one link that is no joint's child
  std::vector<std::string> warnings;  // recoverable oddities, "file:line: ..."

  int findLink(const std::string& name) const;
  // The joint whose child is `link`, or -1 for the root.
  int parentJointOf(int link) const;
};

// URDF rotation from roll, pitch, yaw: R = Rz(yaw) · Ry(pitch) · Rx(roll).
[[nodiscard]] Eigen::Matrix3d UrdfRpyToRotation(const Eigen::Vector3d& rpy);

// Throws DataError at file:line for malformed input: XML syntax, missing or
// unknown link names, a link with two parents, cycles, no single root, unknown
// joint types, negative mass or inertia diagonal, non-numeric or wrong-count
// numbers, a zero axis.
[[nodiscard]] RobotDescription ParseUrdf(const std::string& xml_text, const std::string& file_name);

// A URDF rooted at an empty link with a `floating` joint to the real base (Isaac / MuJoCo-oriented
// exporters: <link name="world"/> <joint type="floating"> world -> base_link): the floating joint is
// a free base. When the root link is massless (< 1e-6 kg) and its only joint is floating, this removes
// that root link and joint, so the joint's child becomes the root (to be put on a free mobilizer), and
// returns a note "file:line: ..." saying so; otherwise it changes nothing and returns "". The joint's
// origin is dropped (a free base's pose is absolute); a non-identity origin adds a warning.
std::string TakeFloatingRootJointAsFreeBase(RobotDescription& description);
// Same shape, for a fixed base: the floating joint becomes a fixed joint (the base welded at its
// origin). Returns the note, or "".
std::string WeldFloatingRootJoint(RobotDescription& description);
[[nodiscard]] RobotDescription LoadUrdf(const std::string& path);

}  // namespace syn
