// The base's residual split into contact forces (contact_forces.h): the non-negative least-squares
// solver against its optimality conditions, a robot standing still against statics (m g through the
// soles, nothing unexplained), a robot in the air against the whole residual, and a real retargeted walk
// against the free base's own inverse-dynamics force and the friction cone.
#include <gtest/gtest.h>

#include <cmath>
#include <fstream>
#include <cstdio>
#include <random>
#include <string>
#include <vector>

#include <Eigen/QR>

#include "common/model.h"
#include "common/robot_map.h"
#include "common/contact_forces.h"
#include "common/least_norm_cone_combination.h"
#include "common/nonnegative_least_squares.h"
#include "tests/support/demo_motion.h"
#include "tests/support/shared_data.h"
#include "tests/support/standing_pose.h"

namespace syn {
namespace {

using Wrench = Eigen::Matrix<double, 6, 1>;

// Karush–Kuhn–Tucker conditions of min ½‖A x − b‖², x ≥ 0 (sufficient, the problem being convex):
// x ≥ 0, g = Aᵀ(A x − b) ≥ 0, and g = 0 where x > 0.
void ExpectOptimal(const NonnegativeLeastSquares::Rows& a, const Wrench& b, const Eigen::VectorXd& x) {
  const Eigen::VectorXd g = a.transpose() * (a * x - b);
  const double scale = a.colwise().norm().maxCoeff() * b.norm();
  for (int i = 0; i < x.size(); ++i) {
    EXPECT_GE(x(i), 0.0) << i;
    EXPECT_GE(g(i), -1e-9 * scale) << i;
    if (x(i) > 0) {
      EXPECT_NEAR(g(i), 0.0, 1e-9 * scale) << i;
    }
  }
}

TEST(NonnegativeLeastSquares, MeetsTheOptimalityConditions) {
  std::mt19937_64 random(7);
  std::normal_distribution<double> normal;
  NonnegativeLeastSquares solver(40);
  int with_active_bounds = 0;
  for (int trial = 0; trial < 200; ++trial) {
    const int n = 1 + trial % 40;
    NonnegativeLeastSquares::Rows a(6, n);
    for (int i = 0; i < a.size(); ++i) a.data()[i] = normal(random);
    Wrench b;
    for (int i = 0; i < 6; ++i) b(i) = 100 * normal(random);
    Eigen::VectorXd x(n);
    solver.solve(a, b, x);
    ExpectOptimal(a, b, x);
    with_active_bounds += (x.array() == 0).any();
  }
  EXPECT_GT(with_active_bounds, 150);  // the bounds mattered, not only unconstrained solves
}

TEST(NonnegativeLeastSquares, RecoversAnExactNonnegativeCombination) {
  std::mt19937_64 random(11);
  std::uniform_real_distribution<double> uniform(-1, 1);
  NonnegativeLeastSquares::Rows a(6, 32);
  for (int i = 0; i < a.size(); ++i) a.data()[i] = uniform(random);
  Eigen::VectorXd truth = Eigen::VectorXd::Zero(32);
  truth(3) = 2.0, truth(17) = 0.5, truth(30) = 1.25;
  const Wrench b = a * truth;
  Eigen::VectorXd x(32);
  NonnegativeLeastSquares(32).solve(a, b, x);
  EXPECT_LT((a * x - b).norm(), 1e-10 * b.norm());
  EXPECT_GE(x.minCoeff(), 0.0);
}

class ContactForces : public ::testing::Test {
 protected:
  static Model G1() { return Model::Load(testing::SourcePath(testing::kG1Urdf)); }
  static RobotMap G1Map() { return LoadRobotMap(testing::SourcePath(testing::kG1Map)); }
};

// The inverse-dynamics forces of standing still in the zero pose on both soles (the workspace left there).
Eigen::VectorXd StandingStillForces(const Model& model, const RobotMap& map, Workspace& workspace) {
  const Eigen::VectorXd still = Eigen::VectorXd::Zero(model.nu());
  Eigen::VectorXd tau(model.nu());
  workspace.setQ(testing::StandingZeroPose(model, map));
  workspace.setU(still);
  workspace.calcInverseDynamics(still, tau);
  return tau;
}

// Still, both soles flat on the floor, the centre of mass between them: the soles carry the weight and
// nothing is left over.
void ExpectStandingCarriesWeight(const Model& model, const RobotMap& map) {
  Workspace workspace(model);
  const Eigen::VectorXd still = Eigen::VectorXd::Zero(model.nu());
  const Eigen::VectorXd tau = StandingStillForces(model, map, workspace);
  ContactForceSplit split(model, map.feet, {});
  ASSERT_TRUE(split.hasBase());
  const std::vector<int64_t> planted(map.feet.size(), 1);
  ContactForceFrame frame;
  split.split(workspace, still, tau, planted.data(), frame);
  const double weight = model.totalMass() * model.gravity();
  EXPECT_NEAR(frame.residual(5), weight, 1e-9 * weight);
  EXPECT_NEAR(frame.residual.head<5>().norm(), 0.0, 1e-6 * weight);  // no moment about the centre of mass
  EXPECT_LT(frame.unexplained.norm(), 1e-6 * weight);
  Eigen::Vector3d total = Eigen::Vector3d::Zero();
  for (const Eigen::Vector3d& force : frame.foot_force) {
    EXPECT_GT(force.z(), 0.2 * weight);  // each foot takes a share
    total += force;
  }
  EXPECT_NEAR(total.z(), weight, 1e-6 * weight);
  EXPECT_NEAR(total.head<2>().norm(), 0.0, 1e-6 * weight);
  // Per sole point, feet one after another: each foot's points add up to the foot's force.
  size_t point = 0;
  for (size_t f = 0; f < map.feet.size(); ++f) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (size_t p = 0; p < map.feet[f].sole_points.size(); ++p) sum += frame.point_force[point++];
    EXPECT_LT((sum - frame.foot_force[f]).norm(), 1e-9 * weight) << "foot " << f;
  }
  EXPECT_EQ(point, frame.point_force.size());
}

// min ‖x‖ subject to A x = w, x ≥ 0 by enumeration: at the optimum the positive entries S are the
// least-norm solution of A_S y = w (the optimality conditions give x_S = A_Sᵀ μ), so the best feasible
// one over every subset of columns is it. Exact and independent of the active-set method; 2ⁿ solves.
Eigen::VectorXd LeastNormByEnumeration(const NonnegativeLeastSquares::Rows& a, const Wrench& w) {
  const int n = static_cast<int>(a.cols());
  Eigen::VectorXd best;
  for (int subset = 1; subset < (1 << n); ++subset) {
    std::vector<int> columns;
    for (int c = 0; c < n; ++c) {
      if (subset & (1 << c)) columns.push_back(c);
    }
    Eigen::MatrixXd sub(6, static_cast<Eigen::Index>(columns.size()));
    for (size_t k = 0; k < columns.size(); ++k) sub.col(static_cast<Eigen::Index>(k)) = a.col(columns[k]);
    const Eigen::VectorXd y = sub.completeOrthogonalDecomposition().solve(w);
    if (y.minCoeff() < 0 || (sub * y - w).norm() > 1e-9 * w.norm()) continue;
    Eigen::VectorXd x = Eigen::VectorXd::Zero(n);
    for (size_t k = 0; k < columns.size(); ++k) x(columns[k]) = y(static_cast<Eigen::Index>(k));
    if (best.size() == 0 || x.norm() < best.norm()) best = x;
  }
  return best;
}

// The optimality conditions of min ½‖x‖² subject to A x = w, x ≥ 0 for the solver's x from `start`:
// x ≥ 0, A x = w, and x = max(0, Aᵀμ) for the μ its positive entries give (x_P = A_Pᵀ μ), checked where
// those entries determine μ. Returns whether they did.
bool ExpectLeastNorm(const NonnegativeLeastSquares::Rows& a, const Eigen::VectorXd& start, const Eigen::VectorXd& x,
                     const std::string& label) {
  const Wrench w = a * start;
  EXPECT_GE(x.minCoeff(), 0.0) << label;
  EXPECT_LT((a * x - w).norm(), 1e-10 * w.norm()) << label;
  EXPECT_LE(x.norm(), start.norm() * (1 + 1e-12)) << label;
  std::vector<Eigen::Index> positive;
  for (Eigen::Index c = 0; c < x.size(); ++c) {
    if (x(c) > 1e-9 * x.norm()) positive.push_back(c);
  }
  Eigen::MatrixXd a_positive(static_cast<Eigen::Index>(positive.size()), 6);
  Eigen::VectorXd x_positive(static_cast<Eigen::Index>(positive.size()));
  for (size_t k = 0; k < positive.size(); ++k) {
    a_positive.row(static_cast<Eigen::Index>(k)) = a.col(positive[k]).transpose();
    x_positive(static_cast<Eigen::Index>(k)) = x(positive[k]);
  }
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> qr(a_positive);
  if (qr.rank() < 6) return false;
  const Eigen::Matrix<double, 6, 1> mu = qr.solve(x_positive);
  const double tolerance = 1e-7 * x.norm();
  EXPECT_LT((a_positive * mu - x_positive).norm(), tolerance) << label << ": no μ gives the positive entries";
  for (Eigen::Index c = 0; c < x.size(); ++c) {
    if (x(c) <= 1e-9 * x.norm()) {
      EXPECT_LE(a.col(c).dot(mu), tolerance) << label << ", column " << c << " should be freed";
    }
  }
  return true;
}

// Random cones of sole-like columns and wrenches inside them, many on the cone's boundary (half the
// mixing weights zero): the split reproduces the wrench, stays non-negative, and is the least-norm one.
TEST(LeastNormConeCombination, MatchesEnumerationOfEverySupport) {
  std::mt19937 random(11);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  LeastNormConeCombination solver(64);
  int most_iterations = 0;
  for (int trial = 0; trial < 40; ++trial) {
    const int n = trial < 30 ? 8 + 2 * (trial % 3) : 64;  // the last ten as many columns as G1's two feet have
    NonnegativeLeastSquares::Rows a(6, n);
    for (int c = 0; c < n; ++c) {
      const Eigen::Vector3d arm(uniform(random), uniform(random), -0.7);
      const Eigen::Vector3d edge(0.8 * uniform(random), 0.8 * uniform(random), 1.0);
      a.col(c) << arm.cross(edge), edge;
    }
    Eigen::VectorXd mix(n);
    for (int c = 0; c < n; ++c) mix(c) = std::max(0.0, uniform(random)) * 100;
    const Wrench w = a * mix;
    Eigen::VectorXd x = mix;
    const int iterations = solver.solve(a, x);
    most_iterations = std::max(most_iterations, iterations);
    ExpectLeastNorm(a, mix, x, "trial " + std::to_string(trial));
    if (n <= 12) {
      const Eigen::VectorXd reference = LeastNormByEnumeration(a, w);
      ASSERT_EQ(reference.size(), n);
      EXPECT_LT((x - reference).norm(), 1e-8 * reference.norm()) << "trial " << trial;
    }
  }
  std::cout << "least-norm split: at most " << most_iterations << " active-set iterations\n";
}

// The cones of G1's soles as syn-simulate meets them: one or both feet flat, their 4 sole points with 8
// pyramid edges each (μ 0.8), arms from a centre of mass 0.7 m up, and wrenches on the cone's faces (three
// quarters of the mixing weights zero), where most columns sit at zero at the optimum.
TEST(LeastNormConeCombination, SoleConesGiveTheLeastNormSplit) {
  std::mt19937 random(5);
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  const std::vector<Eigen::Vector3d> points = {{-0.05, 0.025, 0}, {-0.05, -0.025, 0}, {0.12, 0.03, 0}, {0.12, -0.03, 0}};
  const Eigen::Vector3d centre(0.03, 0.0, 0.7);
  LeastNormConeCombination solver(64);
  int most_iterations = 0, checked = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const int feet = 1 + trial % 2;
    const int n = feet * 4 * 8;
    NonnegativeLeastSquares::Rows a(6, n);
    for (int f = 0, c = 0; f < feet; ++f) {
      const Eigen::Vector3d foot(0.02 * f, f == 0 ? 0.1 : -0.1, 0.0);
      for (const Eigen::Vector3d& point : points) {
        for (int k = 0; k < 8; ++k, ++c) {
          const Eigen::Vector3d edge(0.8 * std::cos(M_PI * k / 4), 0.8 * std::sin(M_PI * k / 4), 1.0);
          a.col(c) << (foot + point - centre).cross(edge), edge;
        }
      }
    }
    Eigen::VectorXd mix(n);
    for (int c = 0; c < n; ++c) mix(c) = uniform(random) < 0.75 ? 0.0 : 50 * uniform(random);
    if (mix.isZero()) continue;
    Eigen::VectorXd x = mix;
    const int iterations = solver.solve(a, x);
    most_iterations = std::max(most_iterations, iterations);
    EXPECT_LT(iterations, 2 * n) << "trial " << trial;
    if (ExpectLeastNorm(a, mix, x, "trial " + std::to_string(trial))) ++checked;
  }
  EXPECT_GT(checked, 300);  // most optima have six or more positive entries spanning the wrenches
  std::cout << "G1 sole cones: at most " << most_iterations << " active-set iterations; " << checked
            << " optima checked by their multipliers\n";
}

// Real problems on which the method cycled at a degenerate vertex (more columns at zero than the wrench
// needs), freeing a column and holding it again without a move, until its iteration cap (4n + 10): on
// CMU 07_06 and 02_01 onto G1 in ground mode, a quarter of the calls, and the result was then the iterate
// it stopped at (one in 28 sampled 0.16 % above the least norm). Eight of them, from syn-simulate, with
// SciPy's solution of each (the fixture's header says how).
TEST(LeastNormConeCombination, DegenerateVerticesOfRealSoleConesDoNotCycle) {
  std::ifstream file(testing::SourcePath("tests/common/fixtures/least_norm_cycling.txt"));
  ASSERT_TRUE(file) << "fixture missing";
  LeastNormConeCombination solver(64);
  std::string line;
  int problems = 0;
  while (std::getline(file, line)) {
    if (line.rfind("problem ", 0) != 0) continue;
    const int n = std::stoi(line.substr(8));
    NonnegativeLeastSquares::Rows a(6, n);
    Eigen::VectorXd start(n);
    for (int r = 0; r < 6; ++r) {
      for (int c = 0; c < n; ++c) file >> a(r, c);
    }
    Eigen::VectorXd reference(n);
    for (int c = 0; c < n; ++c) file >> start(c);
    for (int c = 0; c < n; ++c) file >> reference(c);
    ASSERT_TRUE(file) << "problem " << problems << " is cut short";
    Eigen::VectorXd x = start;
    const int iterations = solver.solve(a, x);
    EXPECT_LT(iterations, 2 * n) << "problem " << problems << " (" << n << " columns)";
    ExpectLeastNorm(a, start, x, "problem " + std::to_string(problems));
    // Their optima have too few positive entries to determine μ: against SciPy's instead.
    EXPECT_LT((x - reference).norm(), 1e-8 * reference.norm()) << "problem " << problems;
    ++problems;
  }
  EXPECT_EQ(problems, 8);
}

// Two planted G1 feet: the split of a wrench moves continuously with it. (The non-negative fit alone
// lands on a vertex of the many splits two feet allow, and the share each foot carries jumped by half
// the weight between neighbouring wrenches: the joint torques syn-simulate computes from it with it.)
TEST_F(ContactForces, TwoFeetShareTheLoadContinuously) {
  const Model model = G1();
  const RobotMap map = G1Map();
  Workspace workspace(model);
  const Eigen::VectorXd still = Eigen::VectorXd::Zero(model.nu());
  const Eigen::VectorXd tau = StandingStillForces(model, map, workspace);
  ContactForceSplit split(model, map.feet, {});
  const std::vector<int64_t> planted(map.feet.size(), 1);
  const double weight = model.totalMass() * model.gravity();
  ContactForceFrame frame;
  double previous_left = -1, largest_jump = 0;
  // A base pitch moment swept in small steps, well inside what the soles explain.
  for (int step = 0; step <= 200; ++step) {
    Eigen::VectorXd swept = tau;
    swept(1) += (step - 100) * 0.05;  // N·m about the base's y axis
    split.split(workspace, still, swept, planted.data(), frame);
    ASSERT_LT(frame.unexplained.norm(), 1e-6 * weight) << "step " << step;
    const double left = frame.foot_force[0].z();
    if (previous_left >= 0) largest_jump = std::max(largest_jump, std::abs(left - previous_left));
    previous_left = left;
    EXPECT_NEAR(left, frame.foot_force[1].z(), 0.05 * weight) << "a symmetric stance shares the load";
  }
  EXPECT_LT(largest_jump, 0.01 * weight);
}

TEST_F(ContactForces, StandingStillTheSolesCarryTheWeight) { ExpectStandingCarriesWeight(G1(), G1Map()); }

TEST_F(ContactForces, StandingStillOnAVirtualBaseChain) {
  const std::string urdf = "robots/humanoid_synergies/HRP4c_optitrack_model.urdf";
  SYN_REQUIRE_SHARED(urdf);
  const Model model = Model::Load(testing::SharedPath(urdf));
  ASSERT_EQ(model.floatingBase(), FloatingBase::kFixed);  // HRP-4C's floating_base_p1..r3 carry the residual
  RobotMap map = LoadRobotMap(testing::SourcePath("manifests/robots/hrp4c.toml"));
  // In HRP-4C's zero pose the centre of mass is 1.8 cm behind the map's heel points, where no sole force
  // can hold it: soles reaching 10 cm further back put it over them.
  for (RobotFoot& foot : map.feet) {
    for (const double y : {0.05, -0.05}) foot.sole_points.push_back({-0.12, y, -0.08});
  }
  ExpectStandingCarriesWeight(model, map);
}

// A wrench the soles cannot carry (a pitching moment far past what the feet's length allows, with a
// sideways push): the row weights decide which part the fit leaves out. Each fit is the best in its own
// weighting, so it leaves less of its own weighted error than the other; weighting the tilting moments
// leaves less of them unexplained and more of the force. Weights of one are the unweighted fit exactly.
TEST_F(ContactForces, RowWeightsDecideWhatAnOverloadedStanceLeavesOut) {
  const Model model = G1();
  const RobotMap map = G1Map();
  Workspace workspace(model);
  const Eigen::VectorXd still = Eigen::VectorXd::Zero(model.nu());
  StandingStillForces(model, map, workspace);
  ContactForceSplit split(model, map.feet, {});
  const std::vector<int64_t> planted(map.feet.size(), 1);
  const double weight = model.totalMass() * model.gravity();
  Wrench wanted;
  wanted << 0.0, 150.0, 0.0, 0.0, 0.3 * weight, weight;  // 150 N·m about y: the soles reach about ±35
  ContactForceFrame plain, weighted, ones;
  split.fit(workspace, still, wanted, planted.data(), plain);
  Wrench tilt_first;
  tilt_first << 3.0, 3.0, 1.0, 1.0, 1.0, 1.0;
  split.fit(workspace, still, wanted, planted.data(), weighted, tilt_first);
  split.fit(workspace, still, wanted, planted.data(), ones, Wrench::Ones());
  std::printf("overloaded stance, unexplained tilting moment / force: one to one %.1f N·m / %.1f N, tilt weighted 3 %.1f N·m / %.1f N\n",
              plain.unexplained.head<2>().norm(), plain.unexplained.tail<3>().norm(), weighted.unexplained.head<2>().norm(),
              weighted.unexplained.tail<3>().norm());
  EXPECT_EQ(ones.unexplained, plain.unexplained);
  ASSERT_GT(plain.unexplained.head<2>().norm(), 50.0) << "the moment is past what the soles carry";
  EXPECT_LT(weighted.unexplained.head<2>().norm(), 0.8 * plain.unexplained.head<2>().norm());
  EXPECT_GT(weighted.unexplained.tail<3>().norm(), plain.unexplained.tail<3>().norm());
  const auto cost = [](const Wrench& rows, const Wrench& error) { return rows.cwiseProduct(error).squaredNorm(); };
  EXPECT_LE(cost(tilt_first, weighted.unexplained), cost(tilt_first, plain.unexplained) * (1 + 1e-12));
  EXPECT_LE(cost(Wrench::Ones(), plain.unexplained), cost(Wrench::Ones(), weighted.unexplained) * (1 + 1e-12));
  // Both splits are admissible and add up to what they explain.
  for (const ContactForceFrame* frame : {&plain, &weighted}) {
    Eigen::Vector3d total = Eigen::Vector3d::Zero();
    for (const Eigen::Vector3d& force : frame->point_force) {
      EXPECT_GE(force.z(), 0.0);
      EXPECT_LE(force.head<2>().norm(), 0.8 * force.z() + 1e-9 * weight);
      total += force;
    }
    EXPECT_LT((total - (frame->residual - frame->unexplained).tail<3>()).norm(), 1e-9 * weight);
  }
}

TEST_F(ContactForces, InTheAirNothingIsExplained) {
  const Model model = G1();
  const RobotMap map = G1Map();
  Workspace workspace(model);
  Eigen::VectorXd q = testing::StandingZeroPose(model, map);
  q(6) += 0.1;  // base z: every sole point 10 cm up
  Eigen::VectorXd u = Eigen::VectorXd::Zero(model.nu()), udot = u, tau(model.nu());
  u(0) = 0.3, u(4) = 0.2;  // turning and moving: centrifugal terms in the residual too
  udot(2) = 1.0;
  workspace.setQ(q);
  workspace.setU(u);
  workspace.calcInverseDynamics(udot, tau);
  ContactForceSplit split(model, map.feet, {});
  const std::vector<int64_t> planted(map.feet.size(), 1);
  ContactForceFrame frame;
  split.split(workspace, u, tau, planted.data(), frame);
  EXPECT_EQ((frame.unexplained - frame.residual).norm(), 0.0);
  for (const Eigen::Vector3d& force : frame.foot_force) EXPECT_EQ(force.norm(), 0.0);
  // The free base's force entries are the residual force itself (ground frame), whatever point the
  // moment is taken about.
  EXPECT_LT((frame.residual.tail<3>() - tau.segment<3>(3)).norm(), 1e-9 * tau.segment<3>(3).norm());
}

// A real walk (CMU 02_01 onto the G1, as the demo runs it): every frame's contact forces are admissible,
// and with the unexplained force they add up to the free base's inverse-dynamics force.
TEST_F(ContactForces, RealWalkForcesAreAdmissibleAndAddUp) {
  const MotionData& motion = testing::DemoMotionOnG1("02_01");
  ASSERT_FALSE(motion.contact_force.empty());
  ASSERT_EQ(motion.unexplained_wrench.size(), static_cast<size_t>(motion.frames()) * 6);
  const size_t feet = motion.contact_feet.size(), nu = static_cast<size_t>(motion.nu());
  const double weight = motion.total_mass * 9.80665, friction = 0.8;
  double vertical = 0;
  int64_t carried = 0;
  for (int64_t t = 0; t < motion.frames(); ++t) {
    Eigen::Vector3d total = Eigen::Vector3d::Zero();
    for (size_t f = 0; f < feet; ++f) {
      const Eigen::Vector3d force(&motion.contact_force[(static_cast<size_t>(t) * feet + f) * 3]);
      EXPECT_GE(force.z(), 0.0) << "frame " << t;
      EXPECT_LE(force.head<2>().norm(), friction * force.z() + 1e-9 * weight) << "frame " << t;
      total += force;
    }
    const Eigen::Vector3d unexplained(&motion.unexplained_wrench[static_cast<size_t>(t) * 6 + 3]);
    const Eigen::Vector3d base_force(&motion.tau[static_cast<size_t>(t) * nu + 3]);
    ASSERT_LT((total + unexplained - base_force).norm(), 1e-6 * weight) << "frame " << t;
    vertical += total.z();
    carried += total.z() > 0;
  }
  // The soles carry the body over the walk (the motion's vertical accelerations average out), and in
  // most frames: those with neither foot down are few.
  EXPECT_NEAR(vertical / static_cast<double>(motion.frames()), weight, 0.15 * weight);
  EXPECT_GT(carried, motion.frames() * 8 / 10);
}

}  // namespace
}  // namespace syn
