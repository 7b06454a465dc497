#include "common/urdf.h"

#include <charconv>
#include <cmath>
#include <map>
#include <sstream>

#include <tinyxml2.h>

#include "common/error.h"
#include "common/file_bytes.h"
#include "common/text_encoding.h"

namespace syn {
namespace {

// Placeholder inertias (a unit tensor pasted on every link) make every torque, power and momentum wrong
// without any error. A radius of gyration √(I/m) over 0.3 m is more than any link of a human-sized robot
// has (a 0.6 m trunk as a uniform rod: 0.17 m). Links whose inertia is too small to matter (< 0.01 kg m^2:
// virtual joints, end-effector frames) are left out.
void WarnAboutImplausibleInertias(RobotDescription& description) {
  constexpr double kMaxRadiusOfGyration = 0.3, kMinInertia = 0.01;
  int implausible = 0;
  const UrdfLink* worst = nullptr;
  double worst_radius = 0;
  for (const UrdfLink& link : description.links) {
    const double inertia = link.inertial.inertia.diagonal().maxCoeff();
    if (inertia < kMinInertia || link.inertial.mass <= 0) continue;
    const double radius = std::sqrt(inertia / link.inertial.mass);
    if (radius <= kMaxRadiusOfGyration) continue;
    ++implausible;
    if (radius > worst_radius) worst = &link, worst_radius = radius;
  }
  if (!worst) return;
  std::ostringstream text;
  text.precision(3);
  text << description.file << ":" << worst->line << ": " << implausible << " link(s) have a radius of gyration over "
       << kMaxRadiusOfGyration << " m, most of all '" << worst->name << "' (" << worst->inertial.mass << " kg, "
       << worst->inertial.inertia.diagonal().maxCoeff() << " kg m^2: " << worst_radius
       << " m) - placeholder inertias? Torques, power and momentum use them as given";
  description.warnings.push_back(text.str());
}

class UrdfParser {
 public:
  explicit UrdfParser(std::string file) : file_(std::move(file)) {}

  [[noreturn]] void fail(const tinyxml2::XMLElement* element, const std::string& message) const {
    throw DataError(Location::AtLine(file_, element ? element->GetLineNum() : 1), message);
  }

  // Reads exactly `count` numbers from a space-separated attribute.
  std::vector<double> numbers(const tinyxml2::XMLElement* element, const char* attribute, size_t count,
                              const std::vector<double>& fallback) const {
    const char* text = element ? element->Attribute(attribute) : nullptr;
    if (!text) return fallback;
    std::vector<double> values;
    const char* cursor = text;
    const char* end = text + std::strlen(text);
    while (cursor < end) {
      while (cursor < end && std::isspace(static_cast<unsigned char>(*cursor))) ++cursor;
      if (cursor == end) break;
      double value = 0;
      if (*cursor == '+') ++cursor;  // from_chars does not take a leading '+'
      const auto [next, error] = std::from_chars(cursor, end, value);
      if (error != std::errc() || (next < end && !std::isspace(static_cast<unsigned char>(*next)))) {
        fail(element, std::string(element->Name()) + " " + attribute + "=\"" + text + "\": expected " +
                          std::to_string(count) + " numbers");
      }
      values.push_back(value);
      cursor = next;
    }
    if (values.size() != count) {
      fail(element, std::string(element->Name()) + " " + attribute + "=\"" + text + "\": expected " +
                        std::to_string(count) + " numbers, found " + std::to_string(values.size()));
    }
    return values;
  }

  double number(const tinyxml2::XMLElement* element, const char* attribute, double fallback) const {
    return numbers(element, attribute, 1, {fallback})[0];
  }

  Eigen::Isometry3d origin(const tinyxml2::XMLElement* parent) const {
    const tinyxml2::XMLElement* element = parent->FirstChildElement("origin");
    Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
    if (!element) return pose;
    const std::vector<double> xyz = numbers(element, "xyz", 3, {0, 0, 0});
    const std::vector<double> rpy = numbers(element, "rpy", 3, {0, 0, 0});
    pose.linear() = UrdfRpyToRotation({rpy[0], rpy[1], rpy[2]});
    pose.translation() = Eigen::Vector3d(xyz[0], xyz[1], xyz[2]);
    return pose;
  }

  std::string name(const tinyxml2::XMLElement* element, const char* what) const {
    const char* text = element->Attribute("name");
    if (!text || !*text) fail(element, std::string(what) + " without a name");
    return ToUtf8(text);  // names end up in JSON and HDF5: Latin-1 or stray bytes by common/text_encoding.h
  }

  UrdfLink link(const tinyxml2::XMLElement* element) const {
    UrdfLink link;
    link.name = name(element, "link");
    link.line = element->GetLineNum();
    if (const tinyxml2::XMLElement* inertial = element->FirstChildElement("inertial")) {
      link.inertial.origin = origin(inertial);
      const tinyxml2::XMLElement* mass = inertial->FirstChildElement("mass");
      link.inertial.mass = mass ? number(mass, "value", 0.0) : 0.0;
      if (link.inertial.mass < 0) fail(mass, "link '" + link.name + "': negative mass");
      if (const tinyxml2::XMLElement* inertia = inertial->FirstChildElement("inertia")) {
        const double ixx = number(inertia, "ixx", 0), iyy = number(inertia, "iyy", 0), izz = number(inertia, "izz", 0);
        const double ixy = number(inertia, "ixy", 0), ixz = number(inertia, "ixz", 0), iyz = number(inertia, "iyz", 0);
        if (ixx < 0 || iyy < 0 || izz < 0) fail(inertia, "link '" + link.name + "': negative moment of inertia");
        link.inertial.inertia << ixx, ixy, ixz, ixy, iyy, iyz, ixz, iyz, izz;
      }
    }
    return link;
  }

  UrdfJoint joint(const tinyxml2::XMLElement* element, std::vector<std::string>& warnings) const {
    UrdfJoint joint;
    joint.name = name(element, "joint");
    joint.line = element->GetLineNum();
    const char* type = element->Attribute("type");
    const std::string type_name = type ? type : "";
    if (type_name == "revolute") joint.type = UrdfJointType::kRevolute;
    else if (type_name == "continuous") joint.type = UrdfJointType::kContinuous;
    else if (type_name == "prismatic") joint.type = UrdfJointType::kPrismatic;
    else if (type_name == "fixed") joint.type = UrdfJointType::kFixed;
    else if (type_name == "floating") joint.type = UrdfJointType::kFloating;
    else fail(element, "joint '" + joint.name + "': unknown type '" + type_name +
                           "' (expected revolute, continuous, prismatic, fixed or floating)");
    const tinyxml2::XMLElement* parent = element->FirstChildElement("parent");
    const tinyxml2::XMLElement* child = element->FirstChildElement("child");
    if (!parent || !parent->Attribute("link")) fail(element, "joint '" + joint.name + "' has no <parent link=...>");
    if (!child || !child->Attribute("link")) fail(element, "joint '" + joint.name + "' has no <child link=...>");
    joint.parent = ToUtf8(parent->Attribute("link"));
    joint.child = ToUtf8(child->Attribute("link"));
    joint.origin = origin(element);
    if (const tinyxml2::XMLElement* axis = element->FirstChildElement("axis")) {
      const std::vector<double> xyz = numbers(axis, "xyz", 3, {1, 0, 0});
      joint.axis = Eigen::Vector3d(xyz[0], xyz[1], xyz[2]);
      const bool moves = joint.type != UrdfJointType::kFixed && joint.type != UrdfJointType::kFloating;
      if (moves && joint.axis.norm() < 1e-12) fail(axis, "joint '" + joint.name + "': zero axis");
      if (joint.axis.norm() >= 1e-12) joint.axis.normalize();
    }
    if (const tinyxml2::XMLElement* limit = element->FirstChildElement("limit")) {
      joint.has_limits = joint.type == UrdfJointType::kRevolute || joint.type == UrdfJointType::kPrismatic;
      joint.lower = number(limit, "lower", 0.0);
      joint.upper = number(limit, "upper", 0.0);
      joint.velocity = number(limit, "velocity", 0.0);
      joint.effort = number(limit, "effort", 0.0);
      if (joint.has_limits && joint.lower > joint.upper) {
        // Seen in a real file (DLR Toro's virtual base joints): treat as unlimited rather than refuse the robot.
        warnings.push_back(file_ + ":" + std::to_string(limit->GetLineNum()) + ": joint '" + joint.name +
                           "': lower limit " + std::to_string(joint.lower) + " > upper " + std::to_string(joint.upper) +
                           "; limits ignored");
        joint.has_limits = false;
      }
    }
    return joint;
  }

  RobotDescription parse(const std::string& xml_text) {
    tinyxml2::XMLDocument document;
    if (document.Parse(xml_text.c_str(), xml_text.size()) != tinyxml2::XML_SUCCESS) {
      throw DataError(Location::AtLine(file_, document.ErrorLineNum()),
                      std::string("XML: ") + (document.ErrorStr() ? document.ErrorStr() : "syntax error"));
    }
    const tinyxml2::XMLElement* robot = document.FirstChildElement("robot");
    if (!robot) throw DataError(Location::AtLine(file_, 1), "no <robot> element: not a URDF file");
    RobotDescription description;
    description.file = file_;
    description.name = robot->Attribute("name") ? ToUtf8(robot->Attribute("name")) : "";
    std::map<std::string, int> link_index;
    for (const auto* element = robot->FirstChildElement("link"); element; element = element->NextSiblingElement("link")) {
      UrdfLink parsed = link(element);
      if (!link_index.emplace(parsed.name, static_cast<int>(description.links.size())).second) {
        fail(element, "link '" + parsed.name + "' is defined twice");
      }
      description.links.push_back(std::move(parsed));
    }
    if (description.links.empty()) fail(robot, "the robot has no <link>");
    WarnAboutImplausibleInertias(description);
    std::vector<int> parent_joint(description.links.size(), -1);
    for (const auto* element = robot->FirstChildElement("joint"); element; element = element->NextSiblingElement("joint")) {
      UrdfJoint parsed = joint(element, description.warnings);
      const auto parent = link_index.find(parsed.parent);
      const auto child = link_index.find(parsed.child);
      if (parent == link_index.end()) fail(element, "joint '" + parsed.name + "': parent link '" + parsed.parent + "' does not exist");
      if (child == link_index.end()) fail(element, "joint '" + parsed.name + "': child link '" + parsed.child + "' does not exist");
      if (parent_joint[static_cast<size_t>(child->second)] >= 0) {
        fail(element, "link '" + parsed.child + "' has two parent joints ('" +
                          description.joints[static_cast<size_t>(parent_joint[static_cast<size_t>(child->second)])].name +
                          "' and '" + parsed.name + "')");
      }
      parent_joint[static_cast<size_t>(child->second)] = static_cast<int>(description.joints.size());
      description.joints.push_back(std::move(parsed));
    }
    // Exactly one root; walking up from every link must reach it (no cycles).
    for (size_t l = 0; l < description.links.size(); ++l) {
      if (parent_joint[l] >= 0) continue;
      if (description.root_link >= 0) {
        throw DataError(Location::AtLine(file_, description.links[l].line),
                        "two root links ('" + description.links[static_cast<size_t>(description.root_link)].name +
                            "' and '" + description.links[l].name + "'): every link but one must be a joint's child");
      }
      description.root_link = static_cast<int>(l);
    }
    for (size_t l = 0; l < description.links.size(); ++l) {
      int current = static_cast<int>(l);
      for (size_t steps = 0; current != description.root_link; ++steps) {
        const int joint_index = parent_joint[static_cast<size_t>(current)];
        if (joint_index < 0 || steps > description.links.size()) {
          const UrdfJoint& culprit = description.joints[static_cast<size_t>(parent_joint[l] >= 0 ? parent_joint[l] : 0)];
          throw DataError(Location::AtLine(file_, culprit.line),
                          "the joints form a cycle through link '" + description.links[l].name + "'");
        }
        current = link_index[description.joints[static_cast<size_t>(joint_index)].parent];
      }
    }
    if (description.root_link < 0) {
      throw DataError(Location::AtLine(file_, description.joints.empty() ? 1 : description.joints[0].line),
                      "no root link: the joints form a cycle");
    }
    return description;
  }

 private:
  std::string file_;
};

}  // namespace

int RobotDescription::findLink(const std::string& link_name) const {
  for (size_t i = 0; i < links.size(); ++i) {
    if (links[i].name == link_name) return static_cast<int>(i);
  }
  return -1;
}

int RobotDescription::parentJointOf(int link) const {
  for (size_t j = 0; j < joints.size(); ++j) {
    if (joints[j].child == links[static_cast<size_t>(link)].name) return static_cast<int>(j);
  }
  return -1;
}

Eigen::Matrix3d UrdfRpyToRotation(const Eigen::Vector3d& rpy) {
  return (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) * Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
          Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
      .toRotationMatrix();
}

RobotDescription ParseUrdf(const std::string& xml_text, const std::string& file_name) {
  return UrdfParser(file_name).parse(xml_text);
}

namespace {

// The root's floating joint when the root is a massless link whose only joint is floating, else -1.
int FloatingRootJoint(const RobotDescription& description) {
  if (description.root_link < 0) return -1;
  const UrdfLink& root = description.links[static_cast<size_t>(description.root_link)];
  if (root.inertial.mass >= 1e-6) return -1;
  int found = -1;
  for (size_t j = 0; j < description.joints.size(); ++j) {
    if (description.joints[j].parent != root.name) continue;
    if (found >= 0 || description.joints[j].type != UrdfJointType::kFloating) return -1;
    found = static_cast<int>(j);
  }
  return found;
}

}  // namespace

std::string TakeFloatingRootJointAsFreeBase(RobotDescription& description) {
  const int joint_index = FloatingRootJoint(description);
  if (joint_index < 0) return "";
  const UrdfJoint joint = description.joints[static_cast<size_t>(joint_index)];
  const std::string root_name = description.links[static_cast<size_t>(description.root_link)].name;
  if (!joint.origin.isApprox(Eigen::Isometry3d::Identity(), 1e-12)) {
    description.warnings.push_back(description.file + ":" + std::to_string(joint.line) + ": floating joint '" +
                                   joint.name + "' has a non-zero origin, ignored: the free base's pose is absolute");
  }
  description.joints.erase(description.joints.begin() + joint_index);
  description.links.erase(description.links.begin() + description.root_link);
  description.root_link = description.findLink(joint.child);
  return description.file + ":" + std::to_string(joint.line) + ": floating joint '" + joint.name +
         "' from the massless root link '" + root_name + "' taken as the free base of '" + joint.child + "'";
}

std::string WeldFloatingRootJoint(RobotDescription& description) {
  const int joint_index = FloatingRootJoint(description);
  if (joint_index < 0) return "";
  UrdfJoint& joint = description.joints[static_cast<size_t>(joint_index)];
  joint.type = UrdfJointType::kFixed;
  return description.file + ":" + std::to_string(joint.line) + ": floating joint '" + joint.name +
         "' from the massless root link '" + joint.parent + "' welded (fixed base)";
}

RobotDescription LoadUrdf(const std::string& path) { return ParseUrdf(ReadFileText(path), path); }

}  // namespace syn
