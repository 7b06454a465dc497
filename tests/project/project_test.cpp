#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include <Eigen/LU>

#include "common/markers_file.h"
#include "common/motion_integration.h"
#include "common/row_major.h"
#include "stages/ingest/ingest.h"
#include "stages/library/style_library.h"
#include "stages/project/projection.h"
#include "stages/project/torso_null_space.h"
#include "stages/retarget/retarget.h"
#include "stages/segment/segmentation.h"
#include "stages/synergies/synergies.h"
#include "tests/support/demo_motion.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

namespace fs = std::filesystem;

const Model& G1() {
  static const Model model = Model::Load(testing::SourcePath(testing::kG1Urdf));
  return model;
}
int TorsoLink() { return G1().findLinkIndex("torso_link"); }

// The walk style's shared basis from the demo's walking trial.
Eigen::MatrixXd WalkBasis() {
  const MotionData& walk = testing::DemoMotionOnG1("02_01");
  LabelledTrial trial;
  trial.labels.trial = "02_01";
  trial.labels.style = "walk";
  trial.synergies = ComputeTrialSynergies(walk, SegmentMotion(walk, G1(), {}).boundaries, SynergyOptions{3, VelocitySet::kAll, trial.labels});
  return BuildLibrary({trial}, {"02_01"}, 3).styles.at("walk").components;
}

// Text-to-motion output: MDM sample 0 (HumanML3D joints) from ../shared, retargeted onto the G1. The tests on
// it skip visibly when the file is absent; the same checks run on a bundled demo trial in any case.
const char kMdmSample[] = "humanml3d/derived/mdm_sample0_joints_T22x3.npy";
MotionData MdmSampleOnG1() {
  const std::string npy = testing::SharedPath(kMdmSample);
  const std::string markers = fs::temp_directory_path() / ("syn_project_" + std::to_string(::getpid()) + ".markers.h5");
  {
    IntermediateWriter writer(markers, {kMarkersSchema, kMarkersSchemaVersion, "test", {}, nlohmann::json::array()});
    WriteMarkerData(writer, IngestCapture(npy, {}, nullptr));
    writer.commit();
  }
  RetargetOptions retarget;
  retarget.model = testing::SourcePath(testing::kG1Urdf);
  retarget.robot_map = testing::SourcePath(testing::kG1Map);
  retarget.markerset = testing::SourcePath("manifests/markersets/humanml3d22.toml");
  MotionData motion = RetargetFile(markers, retarget, nullptr);
  fs::remove(markers);
  return motion;
}

// Formed matrices, the independent reference: A⁻¹ column by column, J from Simbody's general operator.
struct FormedTask {
  Eigen::MatrixXd minv, jacobian, null_space;
};
FormedTask Form(const Eigen::VectorXd& q) {
  const int nu = G1().nu();
  Workspace workspace(G1());
  workspace.setQ(q);
  FormedTask formed;
  formed.minv.resize(nu, nu);
  Eigen::VectorXd unit(nu), column(nu);
  for (int i = 0; i < nu; ++i) {
    unit.setZero();
    unit[i] = 1;
    workspace.calcMassInverseTimes(unit, column);
    formed.minv.col(i) = column;
  }
  Eigen::Matrix<double, 6, Eigen::Dynamic> frame(6, nu);
  workspace.calcFrameJacobianWithSimbody(TorsoLink(), Eigen::Vector3d::Zero(), frame);
  formed.jacobian = frame.topRows<3>();
  const Eigen::Matrix3d lambda = (formed.jacobian * formed.minv * formed.jacobian.transpose()).inverse();
  formed.null_space = Eigen::MatrixXd::Identity(nu, nu) - formed.minv * formed.jacobian.transpose() * lambda * formed.jacobian;
  return formed;
}

void ExpectDynamicallyConsistentProjector(const MotionData& input) {
  ASSERT_GE(TorsoLink(), 0);
  ASSERT_GT(input.frames(), 0);
  TorsoNullSpace null_space(G1(), TorsoLink());
  const int64_t nq = G1().nq(), nu = G1().nu();
  Eigen::VectorXd out(nu);
  for (int64_t t = 0; t < input.frames(); t += 7) {
    const Eigen::VectorXd q = Eigen::Map<const Eigen::VectorXd>(&input.q[static_cast<size_t>(t * nq)], nq);
    const Eigen::VectorXd u = Eigen::Map<const Eigen::VectorXd>(&input.u[static_cast<size_t>(t * nu)], nu);
    null_space.setConfiguration(q);
    null_space.applyNullSpace(u, out);
    const FormedTask formed = Form(q);
    const double u_scale = formed.jacobian.norm() * u.norm();
    EXPECT_LT((formed.jacobian * out).norm(), 1e-9 * u_scale) << "J N u, frame " << t;
    EXPECT_LT((out - formed.null_space * u).norm(), 1e-9 * (1 + u.norm())) << "O(n) operators vs formed, frame " << t;
    EXPECT_LT((formed.null_space * formed.null_space - formed.null_space).cwiseAbs().maxCoeff(), 1e-9) << "N N = N";
    EXPECT_LT((formed.null_space * formed.minv * formed.jacobian.transpose()).cwiseAbs().maxCoeff(),
              1e-9 * formed.minv.cwiseAbs().maxCoeff()) << "N A^-1 J^T = 0, frame " << t;
  }
}

void ExpectVelocityMinusTorsoMotionInTheStyleSubspace(const MotionData& input) {
  const Eigen::MatrixXd basis = WalkBasis();
  ASSERT_EQ(basis.rows(), 3);
  const ProjectionResult result = ProjectMotion(input, G1(), TorsoLink(), basis, nullptr);
  ASSERT_EQ(result.motion.frames(), input.frames());
  const int64_t nq = G1().nq(), nu = G1().nu();
  for (int64_t t = 0; t < input.frames(); ++t) {
    const Eigen::VectorXd q = Eigen::Map<const Eigen::VectorXd>(&input.q[static_cast<size_t>(t * nq)], nq);
    const Eigen::VectorXd u = Eigen::Map<const Eigen::VectorXd>(&input.u[static_cast<size_t>(t * nu)], nu);
    const Eigen::VectorXd u_hat = Eigen::Map<const Eigen::VectorXd>(&result.motion.u[static_cast<size_t>(t * nu)], nu);
    // P = R S Sᵀ Rᵀ with R turning the base velocities by the frame's heading.
    Eigen::MatrixXd rotation = Eigen::MatrixXd::Identity(nu, nu);
    for (int j = 0; j < 6; ++j) {
      Eigen::VectorXd column = rotation.col(j);
      RotateBaseVelocities(BaseYaw(q.data()), column.data());
      rotation.col(j) = column;
    }
    const Eigen::MatrixXd turned = rotation * basis.transpose();
    const Eigen::MatrixXd projector = turned * turned.transpose();
    const FormedTask formed = Form(q);
    const Eigen::MatrixXd task = Eigen::MatrixXd::Identity(nu, nu) - formed.null_space;
    const Eigen::VectorXd torso = task * projector * u;  // default û_t: the torso part of the reconstruction
    const Eigen::VectorXd in_subspace = u_hat - torso;
    EXPECT_LT((in_subspace - projector * in_subspace).norm(), 1e-9 * (1 + in_subspace.norm())) << "frame " << t;
    EXPECT_LT((in_subspace - projector * formed.null_space * u).norm(), 1e-9 * (1 + u.norm())) << "frame " << t;
  }
  EXPECT_LT(result.worst_task_leak, 1e-12);
  EXPECT_LT(result.worst_subspace_residual, 1e-12);
  // The first pose is the input's; the rest is integrated.
  for (int64_t i = 0; i < nq; ++i) EXPECT_EQ(result.motion.q[static_cast<size_t>(i)], input.q[static_cast<size_t>(i)]);
}

TEST(TorsoNullSpace, IsADynamicallyConsistentProjectorOnTextToMotionFrames) {
  SYN_REQUIRE_SHARED(kMdmSample);
  ExpectDynamicallyConsistentProjector(MdmSampleOnG1());
}

TEST(TorsoNullSpace, IsADynamicallyConsistentProjectorOnADemoTrial) {
  ExpectDynamicallyConsistentProjector(testing::DemoMotionOnG1("13_11"));
}

TEST(Projection, TextToMotionVelocityMinusTorsoMotionLiesInTheStyleSubspace) {
  SYN_REQUIRE_SHARED(kMdmSample);
  ExpectVelocityMinusTorsoMotionInTheStyleSubspace(MdmSampleOnG1());
}

TEST(Projection, DemoTrialVelocityMinusTorsoMotionLiesInTheStyleSubspace) {
  ExpectVelocityMinusTorsoMotionInTheStyleSubspace(testing::DemoMotionOnG1("13_11"));
}

}  // namespace
}  // namespace syn
