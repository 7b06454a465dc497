// The base residual split (stages/retarget/contact_forces.h): the NNLS against its optimality conditions,
// the free base's residual convention against an independent statics computation, and the split on a
// standing G1 (both feet down: all explained; one foot lifted with the centre of mass outside the
// other's sole: a moment no contact can explain).
#include <gtest/gtest.h>

#include <random>

#include "common/model.h"
#include "stages/retarget/contact_forces.h"
#include "tests/support/demo_motion.h"
#include "tests/support/shared_data.h"

namespace syn {
namespace {

TEST(NonNegativeLeastSquares, MeetsTheKarushKuhnTuckerConditions) {
  std::mt19937_64 random(3);
  std::normal_distribution<double> normal;
  for (int trial = 0; trial < 20; ++trial) {
    const int columns = 4 + trial % 12;
    NonNegativeLeastSquares nnls(6, 16);
    Eigen::VectorXd b(6);
    for (int i = 0; i < 6; ++i) b[i] = normal(random);
    for (int j = 0; j < columns; ++j) {
      for (int i = 0; i < 6; ++i) nnls.a()(i, j) = normal(random);
    }
    nnls.solve(columns, b);
    const Eigen::MatrixXd a = nnls.a().leftCols(columns);
    const Eigen::VectorXd x = nnls.x().head(columns);
    const Eigen::VectorXd gradient = a.transpose() * (b - a * x);  // −∇½‖Ax − b‖²
    for (int j = 0; j < columns; ++j) {
      EXPECT_GE(x[j], 0.0);
      EXPECT_LE(gradient[j], 1e-7) << "column " << j << " could still lower the cost";
      if (x[j] > 1e-9) {
        EXPECT_NEAR(gradient[j], 0.0, 1e-7) << "column " << j;
      }
    }
  }
}

struct StandingG1 {
  Model model = Model::Load(testing::SourcePath(testing::kG1Urdf));
  Workspace workspace{model};
  std::vector<Eigen::Vector3d> soles;
  std::vector<int> foot_of_point;
  Eigen::VectorXd q = model.defaultQ();
  Eigen::Matrix<double, 6, 1> residual;

  explicit StandingG1(double lift_right) {
    const std::vector<Eigen::Vector3d> sole = {{-0.05, 0.025, -0.035}, {-0.05, -0.025, -0.035}, {0.12, 0.03, -0.035}, {0.12, -0.03, -0.035}};
    workspace.setQ(q);
    double lowest = 1e9;
    for (const char* link : {"left_ankle_roll_link", "right_ankle_roll_link"}) {
      for (const auto& p : sole) lowest = std::min(lowest, (workspace.findLinkPose(model.findLinkIndex(link)) * p).z());
    }
    q[6] -= lowest;
    workspace.setQ(q);
    int foot = 0;
    for (const char* link : {"left_ankle_roll_link", "right_ankle_roll_link"}) {
      for (const auto& p : sole) {
        soles.push_back(workspace.findLinkPose(model.findLinkIndex(link)) * p + Eigen::Vector3d(0, 0, foot == 1 ? lift_right : 0));
        foot_of_point.push_back(foot);
      }
      ++foot;
    }
    workspace.setU(Eigen::VectorXd::Zero(model.nu()));
    Eigen::VectorXd tau;
    workspace.calcInverseDynamics(Eigen::VectorXd::Zero(model.nu()), tau);
    residual = tau.head<6>();
  }
};

TEST(ContactForceSplit, TheBaseResidualIsTheWrenchThatHoldsTheRobotUp) {
  StandingG1 g1(0.0);
  // Statics, independently: the world holds the weight up at the centre of mass.
  const double weight = g1.model.totalMass() * g1.model.gravity();
  const Eigen::Vector3d com = g1.workspace.findCenterOfMass(), origin = g1.q.segment<3>(4);
  EXPECT_NEAR(g1.residual[5], weight, 1e-6 * weight);
  EXPECT_NEAR(g1.residual[3], 0.0, 1e-6 * weight);
  EXPECT_NEAR(g1.residual[4], 0.0, 1e-6 * weight);
  const Eigen::Vector3d moment = (com - origin).cross(Eigen::Vector3d(0, 0, weight));
  EXPECT_LT((g1.residual.head<3>() - moment).norm(), 1e-6 * weight);
}

TEST(ContactForceSplit, BothFeetDownExplainStandingAndOneFootCannotHoldAnOffsetBody) {
  {
    StandingG1 g1(0.0);
    ContactForceSplit split(8, {});
    std::vector<Eigen::Vector3d> force;
    Eigen::Matrix<double, 6, 1> unexplained;
    split.split(g1.soles, g1.foot_of_point, 2, g1.q.segment<3>(4), g1.residual, force, unexplained);
    EXPECT_LT(unexplained.norm(), 1e-3 * g1.residual.norm()) << unexplained.transpose();
    // Symmetric stance: each foot carries half the weight.
    EXPECT_NEAR(force[0].z(), 0.5 * g1.residual[5], 0.05 * g1.residual[5]);
    EXPECT_NEAR(force[1].z(), 0.5 * g1.residual[5], 0.05 * g1.residual[5]);
  }
  {
    // The right foot 5 cm up: the centre of mass (between the feet) is ~0.1 m beside the left sole.
    StandingG1 g1(0.05);
    ContactForceSplit split(8, {});
    std::vector<Eigen::Vector3d> force;
    Eigen::Matrix<double, 6, 1> unexplained;
    split.split(g1.soles, g1.foot_of_point, 2, g1.q.segment<3>(4), g1.residual, force, unexplained);
    EXPECT_EQ(force[1].norm(), 0.0);
    EXPECT_GT(unexplained.norm(), 5.0) << unexplained.transpose();
  }
}

}  // namespace
}  // namespace syn
