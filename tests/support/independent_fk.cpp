#include "tests/support/independent_fk.h"

#include <set>
#include <sstream>
#include <stdexcept>

#include <tinyxml2.h>

namespace syn::testing {
namespace {

Eigen::Vector3d Triple(const char* text, const Eigen::Vector3d& fallback) {
  if (!text) return fallback;
  std::istringstream in(text);
  Eigen::Vector3d v;
  in >> v.x() >> v.y() >> v.z();
  return v;
}

}  // namespace

IndependentFk::IndependentFk(const std::string& urdf_path) {
  tinyxml2::XMLDocument document;
  if (document.LoadFile(urdf_path.c_str()) != tinyxml2::XML_SUCCESS) throw std::runtime_error("cannot read " + urdf_path);
  const tinyxml2::XMLElement* robot = document.FirstChildElement("robot");
  std::vector<Joint> unordered;
  std::set<std::string> links, children;
  for (auto* link = robot->FirstChildElement("link"); link; link = link->NextSiblingElement("link")) links.insert(link->Attribute("name"));
  for (auto* element = robot->FirstChildElement("joint"); element; element = element->NextSiblingElement("joint")) {
    Joint joint;
    joint.name = element->Attribute("name");
    joint.type = element->Attribute("type");
    joint.parent = element->FirstChildElement("parent")->Attribute("link");
    joint.child = element->FirstChildElement("child")->Attribute("link");
    if (auto* origin = element->FirstChildElement("origin")) {
      const Eigen::Vector3d rpy = Triple(origin->Attribute("rpy"), Eigen::Vector3d::Zero());
      joint.origin.translation() = Triple(origin->Attribute("xyz"), Eigen::Vector3d::Zero());
      joint.origin.linear() = (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
                               Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
                               Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
                                  .toRotationMatrix();
    }
    if (auto* axis = element->FirstChildElement("axis")) joint.axis = Triple(axis->Attribute("xyz"), joint.axis).normalized();
    if (joint.type == "revolute" || joint.type == "continuous") revolute_order_.push_back(joint.name);
    children.insert(joint.child);
    unordered.push_back(joint);
  }
  for (const std::string& link : links) {
    if (!children.count(link)) root_ = link;
  }
  // Parents before children.
  std::set<std::string> placed = {root_};
  while (joints_.size() < unordered.size()) {
    const size_t before = joints_.size();
    for (const Joint& joint : unordered) {
      if (placed.count(joint.parent) && !placed.count(joint.child)) joints_.push_back(joint), placed.insert(joint.child);
    }
    if (joints_.size() == before) throw std::runtime_error(urdf_path + ": joints do not form a tree");
  }
}

std::map<std::string, Eigen::Isometry3d> IndependentFk::poses(const std::map<std::string, double>& values,
                                                              const Eigen::Isometry3d& root) const {
  std::map<std::string, Eigen::Isometry3d> result;
  result[root_] = root;
  for (const Joint& joint : joints_) {
    const auto found = values.find(joint.name);
    const double q = found == values.end() ? 0.0 : found->second;
    Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
    if (joint.type == "revolute" || joint.type == "continuous") motion.linear() = Eigen::AngleAxisd(q, joint.axis).toRotationMatrix();
    if (joint.type == "prismatic") motion.translation() = q * joint.axis;
    result[joint.child] = result.at(joint.parent) * joint.origin * motion;
  }
  return result;
}

std::map<std::string, Eigen::Isometry3d> IndependentFk::poses(const std::vector<std::string>& coordinate_names,
                                                              const double* q, bool free_base) const {
  Eigen::Isometry3d root = Eigen::Isometry3d::Identity();
  size_t first = 0;
  if (free_base) {
    root.linear() = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized().toRotationMatrix();
    root.translation() = Eigen::Vector3d(q[4], q[5], q[6]);
    first = 7;
  }
  std::map<std::string, double> values;
  for (size_t i = first; i < coordinate_names.size(); ++i) values[coordinate_names[i]] = q[i];
  return poses(values, root);
}

}  // namespace syn::testing
