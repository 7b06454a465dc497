// syn-human's model against de Leva (1996) Table 4 as transcribed HERE, separately from
// stages/human/de_leva.cpp (a typo in either shows as a mismatch), and against physics: total mass,
// valid inertias, a URDF the pipeline loads, joint signs as documented.
#include <gtest/gtest.h>
#include <unistd.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <map>
#include <string>

#include "common/error.h"
#include "common/file_bytes.h"
#include "common/model.h"
#include "common/urdf.h"
#include "stages/human/human_model.h"
#include "common/robot_map.h"

namespace syn {
namespace {

namespace fs = std::filesystem;

// de Leva (1996) J. Biomech. 29:1223, Table 4 — transcribed for this test from the paper's table.
// { link, {female: length mm, mass %, CoM %, r_sag %, r_trans %, r_long %}, {male: same} }.
// Head VERT-CERV, upper trunk CERV-XYPH and shank KJC-AJC are the table's alternative definitions.
struct Column {
  double length, mass, com, r_sagittal, r_transverse, r_longitudinal;
};
struct Row {
  const char* segment;  // the test's own name; the link(s) are derived below
  Column female, male;
};
const Row kTable4[] = {
    {"head", {243.7, 6.68, 48.41, 27.1, 29.5, 26.1}, {242.9, 6.94, 50.02, 30.3, 31.5, 26.1}},
    {"upper_trunk", {228.0, 15.45, 50.50, 46.6, 31.4, 44.9}, {242.1, 15.96, 50.66, 50.5, 32.0, 46.5}},
    {"middle_trunk", {205.3, 14.65, 45.12, 43.3, 35.4, 41.5}, {215.5, 16.33, 45.02, 48.2, 38.3, 46.8}},
    {"lower_trunk", {181.5, 12.47, 49.20, 43.3, 40.2, 44.4}, {145.7, 11.17, 61.15, 61.5, 55.1, 58.7}},
    {"upper_arm", {275.1, 2.55, 57.54, 27.8, 26.0, 14.8}, {281.7, 2.71, 57.72, 28.5, 26.9, 15.8}},
    {"forearm", {264.3, 1.38, 45.59, 26.1, 25.7, 9.4}, {268.9, 1.62, 45.74, 27.6, 26.5, 12.1}},
    {"hand", {78.0, 0.56, 74.74, 53.1, 45.4, 33.5}, {86.2, 0.61, 79.00, 62.8, 51.3, 40.1}},
    {"thigh", {368.5, 14.78, 36.12, 36.9, 36.4, 16.2}, {422.2, 14.16, 40.95, 32.9, 32.9, 14.9}},
    {"shank", {438.6, 4.81, 43.52, 26.7, 26.3, 9.2}, {440.3, 4.33, 43.95, 25.1, 24.6, 10.2}},
    {"foot", {228.3, 1.29, 40.14, 29.9, 27.9, 13.9}, {258.1, 1.37, 44.15, 25.7, 24.5, 12.4}},
};
constexpr double kStatureFemale = 1735.0, kStatureMale = 1741.0;  // mm, de Leva's reference subjects

// Where each de Leva segment sits in the model (README): URDF link, and the CoM's signed distance from
// the link frame along the segment's axis as a function of (length L, CoM fraction c).
struct Placement {
  const char* segment;
  const char* link;
  int axis;                             // 2 = z, 0 = x (the foot)
  double (*com)(double length, double fraction);
};
double FromTopEnd(double length, double c) { return length * (1 - c); }  // origin endpoint above the frame
double Downwards(double length, double c) { return -length * c; }        // origin endpoint at the frame, going down
const Placement kPlacements[] = {
    {"head", "head", 2, FromTopEnd},           {"upper_trunk", "chest", 2, FromTopEnd},
    {"middle_trunk", "torso", 2, FromTopEnd},  {"lower_trunk", "pelvis", 2, FromTopEnd},
    {"upper_arm", "left_upper_arm", 2, Downwards}, {"upper_arm", "right_upper_arm", 2, Downwards},
    {"forearm", "left_forearm", 2, Downwards}, {"forearm", "right_forearm", 2, Downwards},
    {"hand", "left_hand", 2, Downwards},       {"hand", "right_hand", 2, Downwards},
    {"thigh", "left_thigh", 2, Downwards},     {"thigh", "right_thigh", 2, Downwards},
    {"shank", "left_shank", 2, Downwards},     {"shank", "right_shank", 2, Downwards},
};

const Column& Lookup(const std::string& segment, bool female) {
  for (const Row& row : kTable4) {
    if (segment == row.segment) return female ? row.female : row.male;
  }
  throw std::logic_error("no row " + segment);
}

class HumanModel : public ::testing::TestWithParam<std::tuple<std::string, double, double>> {
 protected:
  void SetUp() override {
    directory_ = fs::temp_directory_path() / ("syn_human_" + std::to_string(::getpid()));
    fs::create_directories(directory_);
    std::tie(options_.sex, options_.height, options_.mass) = GetParam();
    files_ = BuildHumanModel(options_, &summary_);
    urdf_path_ = (directory_ / "human.urdf").string();
    map_path_ = (directory_ / "human.toml").string();
    WriteFileAtomically(urdf_path_, files_.urdf);
    WriteFileAtomically(map_path_, files_.robot_map);
    description_ = LoadUrdf(urdf_path_);
  }
  void TearDown() override { fs::remove_all(directory_); }

  bool female() const { return options_.sex == "f"; }
  double stature() const { return female() ? kStatureFemale : kStatureMale; }
  // Sum of the table's mass percentages over the whole body (paired segments twice).
  double massPercentSum() const {
    double sum = 0;
    for (const Row& row : kTable4) {
      const std::string name = row.segment;
      const bool single = name == "head" || name.find("trunk") != std::string::npos;
      sum += (single ? 1 : 2) * (female() ? row.female.mass : row.male.mass);
    }
    return sum;
  }
  const UrdfLink& link(const std::string& name) const {
    const int index = description_.findLink(name);
    if (index < 0) throw std::logic_error("no link " + name);
    return description_.links[static_cast<size_t>(index)];
  }

  fs::path directory_;
  HumanModelOptions options_;
  HumanModelFiles files_;
  HumanModelSummary summary_;
  std::string urdf_path_, map_path_;
  RobotDescription description_;
};

TEST_P(HumanModel, TotalMassIsTheSubjectsMass) {
  double sum = 0;
  for (const UrdfLink& l : description_.links) sum += l.inertial.mass;
  EXPECT_NEAR(sum, options_.mass, 1e-9 * options_.mass);
  EXPECT_NEAR(Model::Load(urdf_path_).totalMass(), options_.mass, 1e-9 * options_.mass);
  // The table itself: 100.00 % for males, 99.99 % for females (its rounding).
  EXPECT_NEAR(massPercentSum(), female() ? 99.99 : 100.00, 1e-9);
}

TEST_P(HumanModel, SegmentsCarryDeLevasMassCentreOfMassAndRadiiOfGyration) {
  const double scale = options_.height * 1000 / stature();  // subject / reference stature
  for (const Placement& place : kPlacements) {
    SCOPED_TRACE(place.link);
    const Column& table = Lookup(place.segment, female());
    const double length = table.length * scale / 1000;  // m
    const UrdfLink& l = link(place.link);
    // Mass: the table's percentage (normalised by the table's sum so the body adds up exactly).
    EXPECT_NEAR(l.inertial.mass, options_.mass * table.mass / massPercentSum(), 1e-9);
    EXPECT_NEAR(l.inertial.mass / options_.mass * 100, table.mass, 0.0002 * table.mass);
    // CoM on the segment's axis at the table's fraction of the length.
    const Eigen::Vector3d com = l.inertial.origin.translation();
    EXPECT_NEAR(com[place.axis], place.com(length, table.com / 100), 1e-9);
    EXPECT_NEAR(com[place.axis == 2 ? 0 : 2], 0.0, 1e-12);
    EXPECT_NEAR(com[1], 0.0, 1e-12);
    // Radii of gyration: sagittal about x (antero-posterior), transverse about y, longitudinal about z.
    const Eigen::Matrix3d& inertia = l.inertial.inertia;
    EXPECT_TRUE(l.inertial.origin.linear().isIdentity(1e-12));
    EXPECT_NEAR(std::sqrt(inertia(0, 0) / l.inertial.mass) / length * 100, table.r_sagittal, 1e-6);
    EXPECT_NEAR(std::sqrt(inertia(1, 1) / l.inertial.mass) / length * 100, table.r_transverse, 1e-6);
    EXPECT_NEAR(std::sqrt(inertia(2, 2) / l.inertial.mass) / length * 100, table.r_longitudinal, 1e-6);
  }
  // The feet: the long axis is x (heel to toe), transverse y, sagittal the vertical z.
  for (const char* name : {"left_foot", "right_foot"}) {
    SCOPED_TRACE(name);
    const Column& table = Lookup("foot", female());
    const double length = table.length * scale / 1000;
    const UrdfLink& l = link(name);
    EXPECT_NEAR(l.inertial.mass, options_.mass * table.mass / massPercentSum(), 1e-9);
    const Eigen::Matrix3d& inertia = l.inertial.inertia;
    EXPECT_NEAR(std::sqrt(inertia(0, 0) / l.inertial.mass) / length * 100, table.r_longitudinal, 1e-6);
    EXPECT_NEAR(std::sqrt(inertia(1, 1) / l.inertial.mass) / length * 100, table.r_transverse, 1e-6);
    EXPECT_NEAR(std::sqrt(inertia(2, 2) / l.inertial.mass) / length * 100, table.r_sagittal, 1e-6);
    // CoM: the table's fraction of heel -> toe tip; the heel sits 20 % of the foot length behind the ankle.
    EXPECT_NEAR(l.inertial.origin.translation().x(), -0.2 * length + table.com / 100 * length, 1e-9);
  }
}

TEST_P(HumanModel, InertiasArePhysicallyValid) {
  int massive = 0;
  for (const UrdfLink& l : description_.links) {
    SCOPED_TRACE(l.name);
    if (l.inertial.mass == 0) {  // the massless links between the axes of a multi-DoF joint
      EXPECT_TRUE(l.inertial.inertia.isZero());
      continue;
    }
    ++massive;
    const Eigen::Matrix3d& I = l.inertial.inertia;
    EXPECT_TRUE(I.isApprox(I.transpose()));
    const Eigen::Vector3d moments = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(I).eigenvalues();
    EXPECT_GT(moments.minCoeff(), 0.0);
    EXPECT_GE(moments[0] + moments[1], moments[2]);
    EXPECT_GE(moments[0] + moments[2], moments[1]);
    EXPECT_GE(moments[1] + moments[2], moments[0]);
  }
  EXPECT_EQ(massive, 16);  // head, chest, torso, pelvis, and 2 x (upper arm, forearm, hand, thigh, shank, foot)
}

TEST_P(HumanModel, LoadsAsAFreeFloatingHumanoidWithTheRetargetersJoints) {
  const Model model = Model::Load(urdf_path_);
  EXPECT_TRUE(model.hasFreeBase());
  EXPECT_EQ(model.nu(), 6 + 32);
  EXPECT_EQ(summary_.degrees_of_freedom, 32);
  EXPECT_TRUE(model.warnings().empty()) << model.warnings().front();
  std::map<std::string, int> per_joint;
  for (const std::string& name : model.velocityNames()) {
    for (const char* joint : {"hip", "knee", "ankle", "subtalar", "lumbar", "neck", "shoulder", "elbow", "forearm", "wrist"}) {
      if (name.find(joint) != std::string::npos) ++per_joint[joint];
    }
  }
  EXPECT_EQ(per_joint["hip"], 6);
  EXPECT_EQ(per_joint["knee"], 2);
  EXPECT_EQ(per_joint["ankle"] + per_joint["subtalar"], 4);
  EXPECT_EQ(per_joint["lumbar"], 3);
  EXPECT_EQ(per_joint["neck"], 3);
  EXPECT_EQ(per_joint["shoulder"], 6);
  EXPECT_EQ(per_joint["elbow"] + per_joint["forearm"], 4);
  EXPECT_EQ(per_joint["wrist"], 4);
  // The robot map names only links of this model.
  const RobotMap map = LoadRobotMap(map_path_);
  CheckRobotMapNames(
      map, [&](const std::string& name) { return model.findLinkIndex(name) >= 0; },
      [&](const std::string& name) {
        for (const ModelJoint& joint : model.joints()) {
          if (joint.name == name) return true;
        }
        return false;
      },
      model.name());
  EXPECT_EQ(map.tasks.size(), 9u);
  ASSERT_EQ(map.feet.size(), 2u);
}

// The zero pose stands on its soles; positive joint angles move the segments the documented way.
TEST_P(HumanModel, ZeroPoseStandsAndJointSignsFollowOpenSim) {
  const Model model = Model::Load(urdf_path_);
  Workspace workspace(model);
  const double scale = options_.height * 1000 / stature() / 1000;
  const double thigh = Lookup("thigh", female()).length * scale, shank = Lookup("shank", female()).length * scale;
  const RobotMap map = LoadRobotMap(map_path_);
  Eigen::VectorXd q = model.defaultQ();
  workspace.setQ(q);
  const int left_foot = model.findLinkIndex("left_foot");
  const Eigen::Isometry3d foot = workspace.findLinkPose(left_foot);
  EXPECT_NEAR(foot.translation().z(), -(thigh + shank), 1e-9);
  for (const auto& point : map.feet[0].sole_points) {
    EXPECT_NEAR((foot * Eigen::Vector3d(point[0], point[1], point[2])).z(), -(thigh + shank) - 0.039 * options_.height, 1e-9);
  }
  auto position = [&](const std::string& link, const std::string& joint, double angle) {
    Eigen::VectorXd moved = model.defaultQ();
    const auto& names = model.coordinateNames();
    const auto at = std::find(names.begin(), names.end(), joint);
    if (at == names.end()) throw std::logic_error("no coordinate " + joint);
    moved[at - names.begin()] = angle;
    workspace.setQ(moved);
    return Eigen::Vector3d(workspace.findLinkPose(model.findLinkIndex(link)).translation());
  };
  const double angle = 0.3;
  // Hip flexion brings the knee forward; knee flexion takes the ankle back; dorsiflexion lifts the toes.
  EXPECT_GT(position("left_shank", "left_hip_flexion", angle).x(), 0.05);
  EXPECT_GT(position("right_shank", "right_hip_flexion", angle).x(), 0.05);
  EXPECT_LT(position("left_foot", "left_knee", angle).x(), -0.05);
  // Adduction moves the knee towards the midline on both sides; the shoulder's likewise the elbow.
  EXPECT_LT(position("left_shank", "left_hip_adduction", angle).y(), position("left_shank", "left_hip_adduction", 0).y() - 0.05);
  EXPECT_GT(position("right_shank", "right_hip_adduction", angle).y(), position("right_shank", "right_hip_adduction", 0).y() + 0.05);
  EXPECT_LT(position("left_forearm", "left_shoulder_adduction", angle).y(),
            position("left_forearm", "left_shoulder_adduction", 0).y() - 0.03);
  // Elbow flexion brings the wrist forward; shoulder flexion the elbow; lumbar extension leans the head back.
  EXPECT_GT(position("left_hand", "left_elbow", angle).x(), 0.05);
  EXPECT_GT(position("left_forearm", "left_shoulder_flexion", angle).x(), 0.05);
  EXPECT_LT(position("head", "lumbar_extension", angle).x(), -0.05);
  EXPECT_GT(position("head", "lumbar_bending", angle).y(), -1.0);  // (symmetric range: any sign)
}

INSTANTIATE_TEST_SUITE_P(Subjects, HumanModel,
                         ::testing::Values(std::make_tuple(std::string("m"), 1.741, 73.0),
                                           std::make_tuple(std::string("f"), 1.735, 61.9),
                                           std::make_tuple(std::string("m"), 1.92, 95.5),
                                           std::make_tuple(std::string("f"), 1.58, 48.0)));

TEST(HumanModelOptions, OutOfRangeOrUnknownValuesAreUsageErrors) {
  HumanModelOptions options;
  options.sex = "x";
  EXPECT_THROW((void)BuildHumanModel(options, nullptr), UsageError);
  options.sex = "f";
  options.height = 17.5;  // centimetres by mistake
  EXPECT_THROW((void)BuildHumanModel(options, nullptr), UsageError);
  options.height = 1.75;
  options.mass = -3;
  EXPECT_THROW((void)BuildHumanModel(options, nullptr), UsageError);
}

TEST(HumanModelOptions, MissingHeightAndMassFallBackToDeLevasSubjectWithWarnings) {
  HumanModelOptions options;
  options.sex = "f";
  HumanModelSummary summary;
  (void)BuildHumanModel(options, &summary);
  EXPECT_DOUBLE_EQ(summary.height, 1.735);
  EXPECT_DOUBLE_EQ(summary.mass, 61.9);
  EXPECT_EQ(summary.warnings.size(), 2u);
}

TEST(HumanModelOptions, SameOptionsGiveTheSameBytes) {
  HumanModelOptions options;
  options.height = 1.8, options.mass = 80;
  const HumanModelFiles first = BuildHumanModel(options, nullptr), second = BuildHumanModel(options, nullptr);
  EXPECT_EQ(first.urdf, second.urdf);
  EXPECT_EQ(first.robot_map, second.robot_map);
}

}  // namespace
}  // namespace syn
