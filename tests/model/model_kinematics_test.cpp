// The Simbody model against computations made here straight from the URDF
// XML (tinyxml2 + Eigen), independent of common/urdf.cpp and Simbody.
#include <gtest/gtest.h>

#include <iostream>
#include <tinyxml2.h>

#include <Eigen/Geometry>
#include <cmath>
#include <filesystem>
#include <map>
#include <random>
#include <sstream>

#include "common/model.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

struct XmlJoint {
  std::string name, type, parent, child;
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();
};

struct XmlRobot {
  std::map<std::string, double> link_mass;
  std::map<std::string, XmlJoint> joint_to_child;  // child link -> joint
  std::string root;
};

Eigen::Vector3d Triple(const char* text, Eigen::Vector3d fallback) {
  if (!text) return fallback;
  std::istringstream in(text);
  Eigen::Vector3d v;
  in >> v.x() >> v.y() >> v.z();
  return v;
}

XmlRobot ReadXml(const std::string& path) {
  tinyxml2::XMLDocument document;
  EXPECT_EQ(document.LoadFile(path.c_str()), tinyxml2::XML_SUCCESS);
  XmlRobot robot;
  const tinyxml2::XMLElement* root = document.FirstChildElement("robot");
  for (auto* link = root->FirstChildElement("link"); link; link = link->NextSiblingElement("link")) {
    double mass = 0;
    if (auto* inertial = link->FirstChildElement("inertial")) {
      if (auto* m = inertial->FirstChildElement("mass")) mass = m->DoubleAttribute("value");
    }
    robot.link_mass[link->Attribute("name")] = mass;
  }
  for (auto* joint = root->FirstChildElement("joint"); joint; joint = joint->NextSiblingElement("joint")) {
    XmlJoint parsed;
    parsed.name = joint->Attribute("name");
    parsed.type = joint->Attribute("type");
    parsed.parent = joint->FirstChildElement("parent")->Attribute("link");
    parsed.child = joint->FirstChildElement("child")->Attribute("link");
    if (auto* origin = joint->FirstChildElement("origin")) {
      const Eigen::Vector3d xyz = Triple(origin->Attribute("xyz"), Eigen::Vector3d::Zero());
      const Eigen::Vector3d rpy = Triple(origin->Attribute("rpy"), Eigen::Vector3d::Zero());
      parsed.origin.translation() = xyz;
      parsed.origin.linear() = (Eigen::AngleAxisd(rpy.z(), Eigen::Vector3d::UnitZ()) *
                                Eigen::AngleAxisd(rpy.y(), Eigen::Vector3d::UnitY()) *
                                Eigen::AngleAxisd(rpy.x(), Eigen::Vector3d::UnitX()))
                                   .toRotationMatrix();
    }
    if (auto* axis = joint->FirstChildElement("axis")) parsed.axis = Triple(axis->Attribute("xyz"), parsed.axis);
    if (parsed.axis.norm() > 0) parsed.axis.normalize();
    robot.joint_to_child[parsed.child] = parsed;
  }
  for (const auto& [link, mass] : robot.link_mass) {
    if (!robot.joint_to_child.count(link)) robot.root = link;
  }
  return robot;
}

// World pose of `link` for joint values by name, composing origins and joint motions.
Eigen::Isometry3d IndependentPose(const XmlRobot& robot, const std::string& link,
                                  const std::map<std::string, double>& joint_values, const Eigen::Isometry3d& base) {
  if (link == robot.root) return base;
  const XmlJoint& joint = robot.joint_to_child.at(link);
  Eigen::Isometry3d motion = Eigen::Isometry3d::Identity();
  const auto value = joint_values.find(joint.name);
  const double q = value == joint_values.end() ? 0.0 : value->second;
  if (joint.type == "revolute" || joint.type == "continuous") motion.linear() = Eigen::AngleAxisd(q, joint.axis).toRotationMatrix();
  if (joint.type == "prismatic") motion.translation() = q * joint.axis;
  return IndependentPose(robot, joint.parent, joint_values, base) * joint.origin * motion;
}

// The bundled G1 (byte-identical to ../shared's robots/unitree/g1_29dof.urdf), so the checks run everywhere,
// then every URDF under ../shared/datasets/robots when it exists (its absence is printed).
std::vector<std::string> UrdfsToCheck() {
  std::vector<std::string> files;
  const std::string folder = testing::SharedPath("robots");
  if (std::filesystem::exists(folder)) {
    for (const auto& entry : std::filesystem::recursive_directory_iterator(folder)) {
      if (entry.path().extension() == ".urdf") files.push_back(entry.path().string());
    }
    std::sort(files.begin(), files.end());
  } else {
    std::cout << "[  NOTE    ] shared dataset absent, checked the bundled G1 only: " << folder << "\n";
  }
  files.insert(files.begin(), testing::SourcePath("datasets/robots/unitree_g1/g1_29dof.urdf"));
  return files;
}

TEST(Model, EverySharedUrdfLoadsWithTheMassOfItsLinks) {
  const auto files = UrdfsToCheck();
  if (std::filesystem::exists(testing::SharedPath("robots"))) {
    ASSERT_GE(files.size(), 1u + 8u);
  }
  for (const std::string& file : files) {
    SCOPED_TRACE(file);
    const Model model = Model::Load(file);
    const XmlRobot xml = ReadXml(file);
    double mass = 0;
    for (const auto& [link, link_mass] : xml.link_mass) mass += link_mass;
    EXPECT_NEAR(model.totalMass(), mass, 1e-9 * mass);
    EXPECT_EQ(model.linkNames().size(), xml.link_mass.size());
    EXPECT_EQ(model.nq(), static_cast<int>(model.coordinateNames().size()));
  }
}

TEST(Model, ForwardKinematicsMatchesAnIndependentComputation) {
  std::mt19937 random(2024);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  for (const std::string& file : UrdfsToCheck()) {
    SCOPED_TRACE(file);
    const Model model = Model::Load(file);
    const XmlRobot xml = ReadXml(file);
    Workspace workspace(model);
    double worst_position = 0, worst_angle = 0;
    for (int sample = 0; sample <= 100; ++sample) {
      Eigen::VectorXd q = model.defaultQ();
      Eigen::Isometry3d base = Eigen::Isometry3d::Identity();
      std::map<std::string, double> values;
      if (sample > 0) {
        const int first_joint = model.hasFreeBase() ? 7 : 0;
        if (model.hasFreeBase()) {
          const Eigen::Quaterniond rotation = Eigen::Quaterniond::UnitRandom();
          q.head<4>() << rotation.w(), rotation.x(), rotation.y(), rotation.z();
          q.segment<3>(4) = Eigen::Vector3d(unit(random), unit(random), unit(random));
          base.linear() = rotation.toRotationMatrix();
          base.translation() = q.segment<3>(4);
        }
        for (int i = first_joint; i < model.nq(); ++i) {
          const double low = std::isfinite(model.qLower()[i]) ? std::max(model.qLower()[i], -3.0) : -3.0;
          const double high = std::isfinite(model.qUpper()[i]) ? std::min(model.qUpper()[i], 3.0) : 3.0;
          q[i] = low + (high - low) * unit(random);
          values[model.coordinateNames()[static_cast<size_t>(i)]] = q[i];
        }
      }
      workspace.setQ(q);
      for (size_t link = 0; link < model.linkNames().size(); ++link) {
        const Eigen::Isometry3d expected = IndependentPose(xml, model.linkNames()[link], values, base);
        const Eigen::Isometry3d actual = workspace.findLinkPose(static_cast<int>(link));
        worst_position = std::max(worst_position, (expected.translation() - actual.translation()).norm());
        worst_angle = std::max(worst_angle, Eigen::AngleAxisd(expected.linear().transpose() * actual.linear()).angle());
      }
    }
    EXPECT_LT(worst_position, 1e-9);
    EXPECT_LT(worst_angle, 1e-9);
  }
}

TEST(Model, AutoFloatingBaseFollowsTheUrdfConvention) {
  const Model g1 = Model::Load(testing::SourcePath("datasets/robots/unitree_g1/g1_29dof.urdf"));
  EXPECT_TRUE(g1.hasFreeBase());
  EXPECT_EQ(g1.nq(), 7 + 29);
  EXPECT_EQ(g1.nu(), 6 + 29);
  EXPECT_EQ(g1.coordinateNames()[7], "left_hip_pitch_joint");
  // HRP-4C (a URDF with its own `floating` joint) lives in ../shared only.
  SYN_REQUIRE_SHARED("robots/humanoid_synergies/HRP4c_optitrack_model.urdf");
  const Model hrp = Model::Load(testing::SharedPath("robots/humanoid_synergies/HRP4c_optitrack_model.urdf"));
  EXPECT_FALSE(hrp.hasFreeBase());
  EXPECT_EQ(hrp.coordinateNames()[0], "floating_base_p1");
  EXPECT_EQ(hrp.nq(), hrp.nu());
  ModelOptions free;
  free.floating_base = FloatingBase::kFree;
  EXPECT_TRUE(Model::Load(testing::SharedPath("robots/humanoid_synergies/HRP4c_optitrack_model.urdf"), free).hasFreeBase());
}

}  // namespace
}  // namespace syn
