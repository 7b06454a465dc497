#include "tools/studio/robot_description.h"

#include <deque>
#include <map>

#include <Eigen/Geometry>

#include "common/error.h"
#include "common/urdf.h"

namespace syn {
namespace {

const char* JointTypeName(UrdfJointType type) {
  switch (type) {
    case UrdfJointType::kRevolute: return "revolute";
    case UrdfJointType::kContinuous: return "continuous";
    case UrdfJointType::kPrismatic: return "prismatic";
    case UrdfJointType::kFixed: return "fixed";
    case UrdfJointType::kFloating: return "floating";
  }
  return "fixed";
}

nlohmann::json Vector(const Eigen::Vector3d& v) { return nlohmann::json::array({v.x(), v.y(), v.z()}); }

}  // namespace

nlohmann::json PlayerRobotDescription(const std::string& urdf_path, const Model& model, const RobotMap& map) {
  const RobotDescription urdf = LoadUrdf(urdf_path);
  std::map<std::string, int> column;
  for (size_t i = 0; i < model.coordinateNames().size(); ++i) column[model.coordinateNames()[i]] = static_cast<int>(i);
  std::vector<std::vector<int>> children(urdf.links.size());  // joint indexes, file order
  for (size_t j = 0; j < urdf.joints.size(); ++j) {
    children[static_cast<size_t>(urdf.findLink(urdf.joints[j].parent))].push_back(static_cast<int>(j));
  }
  nlohmann::json links = nlohmann::json::array();
  std::map<std::string, int> index;
  // Breadth-first from the root, children in file order: the order urdf_fk.py gives.
  std::deque<int> order{urdf.root_link};
  while (!order.empty()) {
    const int link = order.front();
    order.pop_front();
    const UrdfLink& urdf_link = urdf.links[static_cast<size_t>(link)];
    index[urdf_link.name] = static_cast<int>(links.size());
    const int joint_index = urdf.parentJointOf(link);
    nlohmann::json entry = {{"name", urdf_link.name},
                            {"parent", joint_index < 0 ? -1 : index.at(urdf.joints[static_cast<size_t>(joint_index)].parent)},
                            {"com", Vector(urdf_link.inertial.origin.translation())},
                            {"mass", urdf_link.inertial.mass}};
    if (joint_index >= 0) {
      const UrdfJoint& joint = urdf.joints[static_cast<size_t>(joint_index)];
      const Eigen::Quaterniond rotation(joint.origin.rotation());
      const auto found = column.find(joint.name);
      entry["joint"] = joint.name;
      entry["type"] = JointTypeName(joint.type);
      entry["xyz"] = Vector(joint.origin.translation());
      entry["quaternion"] = {rotation.w(), rotation.x(), rotation.y(), rotation.z()};
      entry["axis"] = Vector(joint.axis);
      entry["q"] = joint.type != UrdfJointType::kFixed && found != column.end() ? found->second : -1;
    }
    links.push_back(entry);
    for (int j : children[static_cast<size_t>(link)]) {
      order.push_back(urdf.findLink(urdf.joints[static_cast<size_t>(j)].child));
    }
  }
  nlohmann::json base = nlohmann::json::array();
  for (const char* name : {"base_qw", "base_qx", "base_qy", "base_qz", "base_x", "base_y", "base_z"}) {
    const auto found = column.find(name);
    if (found == column.end()) {
      base = nullptr;
      break;
    }
    base.push_back(found->second);
  }
  nlohmann::json feet = nlohmann::json::array();
  for (const RobotFoot& foot : map.feet) {
    const auto found = index.find(foot.link);
    if (found == index.end()) {
      throw DataError(Location::AtLine(map.file, foot.line), "foot link '" + foot.link + "' is not a link of " + urdf_path);
    }
    feet.push_back({{"side", foot.side}, {"link", found->second}, {"sole_points", foot.sole_points}});
  }
  return {{"robot", urdf.name}, {"links", links}, {"base_q", base}, {"feet", feet}};
}

}  // namespace syn
