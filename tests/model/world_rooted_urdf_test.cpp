// URDFs rooted at an empty `world` link with a floating joint to the base (Isaac / MuJoCo-oriented
// exporters): the floating joint is the free base. The same robot without the world link is the
// reference: same coordinates, same links, same forward kinematics.
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "common/error.h"
#include "common/model.h"
#include "common/urdf.h"
#include "tests/support/run_command.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

namespace fs = std::filesystem;

const char* kLegLinks = R"(
  <link name="base_link">
    <inertial><origin xyz="0 0 0.05"/><mass value="5"/><inertia ixx="0.05" iyy="0.05" izz="0.04" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <link name="thigh">
    <inertial><origin xyz="0 0 -0.2"/><mass value="2"/><inertia ixx="0.02" iyy="0.02" izz="0.005" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <link name="shank">
    <inertial><origin xyz="0 0 -0.2"/><mass value="1.5"/><inertia ixx="0.015" iyy="0.015" izz="0.003" ixy="0" ixz="0" iyz="0"/></inertial>
  </link>
  <joint name="hip" type="revolute">
    <parent link="base_link"/><child link="thigh"/><origin xyz="0 0.1 -0.05" rpy="0.1 0 0"/><axis xyz="0 1 0"/>
    <limit lower="-2" upper="2" effort="100" velocity="10"/>
  </joint>
  <joint name="knee" type="revolute">
    <parent link="thigh"/><child link="shank"/><origin xyz="0 0 -0.4"/><axis xyz="0 1 0"/>
    <limit lower="0" upper="2.5" effort="100" velocity="10"/>
  </joint>
)";

class WorldRootedUrdf : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / ("syn_world_urdf_" + std::to_string(::getpid()));
    fs::create_directories(dir_);
    plain_ = (dir_ / "plain.urdf").string();
    world_ = (dir_ / "world.urdf").string();
    std::ofstream(plain_) << "<robot name=\"leg\">" << kLegLinks << "</robot>\n";
    std::ofstream(world_) << "<robot name=\"leg\">\n  <link name=\"world\"/>\n"
                          << "  <joint name=\"world_to_base\" type=\"floating\">\n"
                          << "    <parent link=\"world\"/><child link=\"base_link\"/>\n  </joint>" << kLegLinks << "</robot>\n";
  }
  void TearDown() override { fs::remove_all(dir_); }

  fs::path dir_;
  std::string plain_, world_;
};

TEST_F(WorldRootedUrdf, TheFloatingJointIsTheFreeBase) {
  ModelOptions free;
  free.floating_base = FloatingBase::kFree;
  const Model reference = Model::Load(plain_, free);
  for (FloatingBase requested : {FloatingBase::kAuto, FloatingBase::kFree}) {
    ModelOptions options;
    options.floating_base = requested;
    const Model model = Model::Load(world_, options);
    EXPECT_TRUE(model.hasFreeBase());
    EXPECT_EQ(model.nq(), 9);  // quaternion 4 + position 3 + hip + knee
    EXPECT_EQ(model.coordinateNames(), reference.coordinateNames());
    EXPECT_EQ(model.linkNames(), reference.linkNames());  // "world" is gone
    EXPECT_DOUBLE_EQ(model.totalMass(), 8.5);
    ASSERT_EQ(model.notes().size(), 1u);
    EXPECT_NE(model.notes()[0].find(":3: floating joint 'world_to_base' from the massless root link 'world' taken as "
                                    "the free base of 'base_link'"),
              std::string::npos)
        << model.notes()[0];
    // Same pose, same link poses (turned and moved base, bent hip and knee).
    Eigen::VectorXd q = model.defaultQ();
    const Eigen::Quaterniond turn(Eigen::AngleAxisd(0.7, Eigen::Vector3d(1, 2, 3).normalized()));
    q.head<4>() << turn.w(), turn.x(), turn.y(), turn.z();
    q.segment<3>(4) << 0.3, -0.2, 0.9;
    q[7] = 0.4, q[8] = 1.1;
    Workspace ours(model), theirs(reference);
    ours.setQ(q);
    theirs.setQ(q);
    for (int link = 0; link < static_cast<int>(model.linkNames().size()); ++link) {
      EXPECT_TRUE(ours.findLinkPose(link).isApprox(theirs.findLinkPose(link), 1e-12)) << model.linkNames()[link];
    }
    // Independent check of the shank's origin: base pose * hip origin * Ry(q_hip) * knee origin.
    const Eigen::Vector3d expected =
        Eigen::Vector3d(0.3, -0.2, 0.9) +
        turn * (Eigen::Vector3d(0, 0.1, -0.05) +
                Eigen::AngleAxisd(0.1, Eigen::Vector3d::UnitX()) * (Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitY()) * Eigen::Vector3d(0, 0, -0.4)));
    EXPECT_LT((ours.findLinkPose(model.findLinkIndex("shank")).translation() - expected).norm(), 1e-12);
  }
}

TEST_F(WorldRootedUrdf, AFixedBaseWeldsIt) {
  ModelOptions fixed;
  fixed.floating_base = FloatingBase::kFixed;
  const Model model = Model::Load(world_, fixed);
  EXPECT_FALSE(model.hasFreeBase());
  EXPECT_EQ(model.nq(), 2);
  ASSERT_EQ(model.notes().size(), 1u);
  EXPECT_NE(model.notes()[0].find("welded"), std::string::npos);
}

TEST_F(WorldRootedUrdf, VerboseToolsSaySo) {
  const testing::CommandResult quiet = testing::RunCommand(testing::BinPath("syn-inspect") + " " + world_);
  EXPECT_EQ(quiet.exit_code, 0) << quiet.output;
  EXPECT_EQ(quiet.output.find("taken as the free base"), quiet.output.rfind("taken as the free base"));  // JSON only
  const testing::CommandResult verbose = testing::RunCommand(testing::BinPath("syn-inspect") + " -v " + world_);
  EXPECT_EQ(verbose.exit_code, 0) << verbose.output;
  EXPECT_NE(verbose.output.find("syn-inspect: " + world_ + ":3: floating joint 'world_to_base'"), std::string::npos)
      << verbose.output;
}

TEST_F(WorldRootedUrdf, AFloatingJointInsideTheTreeIsStillRefusedWithItsLine) {
  const std::string inside = (dir_ / "inside.urdf").string();
  std::string text = std::string("<robot name=\"leg\">") + kLegLinks + "</robot>\n";
  const size_t knee = text.find("type=\"revolute\">\n    <parent link=\"thigh\"/>");
  ASSERT_NE(knee, std::string::npos);
  text.replace(knee, std::string("type=\"revolute\"").size(), "type=\"floating\"");
  std::ofstream(inside) << text;
  try {
    (void)Model::Load(inside);
    FAIL() << "a floating knee must be refused";
  } catch (const DataError& error) {
    EXPECT_GT(error.where().line, 0);
    EXPECT_NE(std::string(error.what()).find("joint 'knee': a floating joint is read only as the free base"),
              std::string::npos)
        << error.what();
  }
}

}  // namespace
}  // namespace syn
