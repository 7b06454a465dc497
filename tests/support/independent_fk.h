// A URDF forward kinematics written from the URDF text alone (tinyxml2 +
// Eigen), independent of common/model.h and Simbody: tests check the stages'
// motions with it. Joints: revolute, continuous, prismatic, fixed; the root
// link's pose is given (a free base) or the identity.
#pragma once

#include <map>
#include <string>
#include <vector>

#include <Eigen/Geometry>

namespace syn::testing {

class IndependentFk {
 public:
  explicit IndependentFk(const std::string& urdf_path);

  // World poses of every link for joint values by name (missing joints are 0) and the root link's pose.
  std::map<std::string, Eigen::Isometry3d> poses(const std::map<std::string, double>& joints,
                                                 const Eigen::Isometry3d& root) const;
  // The same from a motion frame: coordinate names as syn-retarget writes them (a free base's
  // coordinates first: quaternion w,x,y,z then position, named by the model; every other coordinate
  // is a URDF joint by name).
  std::map<std::string, Eigen::Isometry3d> poses(const std::vector<std::string>& coordinate_names, const double* q,
                                                 bool free_base) const;
  const std::string& root() const { return root_; }
  const std::vector<std::string>& revoluteJointsInFileOrder() const { return revolute_order_; }

 private:
  struct Joint {
    std::string name, type, parent, child;
    Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();
    Eigen::Vector3d axis = Eigen::Vector3d::UnitX();
  };
  std::vector<Joint> joints_;  // parents before children
  std::vector<std::string> revolute_order_;
  std::string root_;
};

}  // namespace syn::testing
