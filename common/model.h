// A robot model loaded from URDF into Simbody, and the per-thread workspace
// that evaluates kinematics and dynamics on it.
//
// `Model` is immutable after Load() and cheap to copy (it shares the realized
// Simbody system). Each thread makes its own `Workspace` (a Simbody State
// copied from the model's default state plus scratch vectors); per-frame
// calls on a Workspace do not allocate once their output vectors are sized.
//
// Coordinates: with a free base, q = (base quaternion w,x,y,z, base position
// x,y,z in the ground frame, joints...) and u = (base angular velocity,
// base linear velocity — both in the ground frame —, joints...), so nq = nu + 1.
// Without one, q and u are the URDF's non-fixed joints in file order.
// Units SI; ground Z up; gravity −Z.
#pragma once

#include <array>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

namespace syn {

enum class FloatingBase {
  kAuto,   // kFixed when the root link is massless (< 1 mg) and starts a chain of moving joints (the
           // SAI convention of virtual prismatic + revolute base joints, e.g. HRP-4C), else kFree
  kFree,   // a Free mobilizer between ground and the URDF's root link
  kFixed,  // the root link welded to ground; the URDF's own joints used as they are
};

[[nodiscard]] std::string_view FloatingBaseName(FloatingBase base);
// "auto", "free", "fixed"; throws UsageError for anything else.
[[nodiscard]] FloatingBase FloatingBaseFromName(std::string_view name);

struct ModelOptions {
  FloatingBase floating_base = FloatingBase::kAuto;
  double gravity = 9.80665;  // m/s², along −Z (standard gravity)
  // Joint -> [lower, upper]: each named joint's position limits become their intersection with the URDF's
  // (the robot map's [joint_ranges], for retargeting). UsageError where the two do not overlap.
  std::map<std::string, std::array<double, 2>> joint_ranges = {};
};

// One URDF joint as the model realised it.
struct ModelJoint {
  std::string name;
  std::string type;    // "revolute", "continuous", "prismatic", "fixed", "free" (the added base)
  std::string parent;  // link names
  std::string child;
  int q_index = -1;    // first coordinate, -1 for fixed
  int u_index = -1;    // first velocity, -1 for fixed
  // The URDF's joint frame in the parent link frame (the child link's frame at zero motion) and its axis
  // in that frame; identity and x for the added free base.
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();
};

class Model {
 public:
  // Throws DataError (file:line) for a malformed URDF.
  static Model Load(const std::string& urdf_path, const ModelOptions& options = {});

  const std::string& name() const;
  const std::string& sourcePath() const;
  const std::string& sourceSha256() const;  // of the URDF bytes
  FloatingBase floatingBase() const;        // resolved (never kAuto)
  bool hasFreeBase() const;
  int nq() const;
  int nu() const;
  double totalMass() const;  // kg, every link of the URDF
  double gravity() const;
  // [nu]: false for velocities no motor drives — a free base's six, or a virtual free base (three prismatic
  // and three revolute joints through massless links from a massless root, e.g. HRP-4C's
  // floating_base_p1..r3). Mechanical power sums the rest.
  const std::vector<bool>& actuatedVelocities() const;

  const std::vector<std::string>& coordinateNames() const;  // [nq]
  const std::vector<std::string>& velocityNames() const;    // [nu]
  const Eigen::VectorXd& qLower() const;  // [nq], -inf where unlimited (base, continuous joints)
  const Eigen::VectorXd& qUpper() const;  // [nq], +inf where unlimited
  const Eigen::VectorXd& uLimit() const;  // [nu], +inf where the URDF gives none (velocity 0 or absent)
  const Eigen::VectorXd& effortLimit() const;  // [nu], the URDF's joint effort (N·m or N); +inf where none
  Eigen::VectorXd defaultQ() const;       // identity base orientation, zeros

  // Every URDF link, including links merged into their parent by fixed joints.
  const std::vector<std::string>& linkNames() const;
  int findLinkIndex(const std::string& link_name) const;  // -1 if absent
  int freeBaseLink() const;  // the link the added free joint carries (the pelvis), -1 without a free base
  const std::vector<ModelJoint>& joints() const;         // file order, plus the free base first if added
  const std::vector<std::string>& warnings() const;      // what the URDF needed forgiving ("file:line: ...")
  const std::vector<std::string>& notes() const;         // how it was read, for -v (a floating root joint taken as the free base)

  struct Impl;
  const Impl& impl() const { return *impl_; }

 private:
  explicit Model(std::shared_ptr<const Impl> impl) : impl_(std::move(impl)) {}
  std::shared_ptr<const Impl> impl_;
};

// Model::Load with the floating base given by name ("auto", "free", "fixed"), as every tool's
// --floating-base flag takes it. Throws UsageError for another name.
[[nodiscard]] Model LoadModel(const std::string& urdf_path, std::string_view floating_base_name);

class Workspace {
 public:
  explicit Workspace(const Model& model);
  ~Workspace();
  Workspace(Workspace&&) noexcept;
  Workspace& operator=(Workspace&&) noexcept;

  const Model& model() const { return model_; }

  // Sets the configuration (nq; a free base's quaternion is normalised) and
  // realises positions. Cost: about 15 µs for a 30-dof humanoid.
  void setQ(const Eigen::VectorXd& q);
  // Sets the generalized velocities (nu).
  void setU(const Eigen::VectorXd& u);
  const Eigen::VectorXd& getQ() const;
  const Eigen::VectorXd& getU() const;

  // World pose of a link frame (URDF link origin and axes). Requires setQ.
  Eigen::Isometry3d findLinkPose(int link) const;

  // 6 × nu Jacobian of a point fixed on a link (given in the link frame):
  // rows 0–2 the link's angular velocity, rows 3–5 the point's linear
  // velocity, both in the ground frame. Requires setQ.
  void calcFrameJacobian(int link, const Eigen::Vector3d& point_in_link,
                         Eigen::Matrix<double, 6, Eigen::Dynamic>& jacobian);
  // The same from Simbody's general operator (8 µs): the reference the tests hold the analytic one to.
  void calcFrameJacobianWithSimbody(int link, const Eigen::Vector3d& point_in_link,
                                    Eigen::Matrix<double, 6, Eigen::Dynamic>& jacobian);

  // out = A(q) v, the mass matrix times a vector, in O(n) (Simbody
  // multiplyByM; A is never formed). Requires setQ.
  void calcMassTimes(const Eigen::VectorXd& v, Eigen::VectorXd& out);
  // out = A(q) v at the configuration q given here (a free base's quaternion is normalised, as setQ does),
  // by one O(n) recursive pass — body poses, then composite momenta from the leaves to the root — that
  // neither realises nor changes the Simbody state (getQ() stays). The same product as setQ(q) followed
  // by calcMassTimes(v), to rounding, in about a tenth of the time: Debian's Simbody is built with its
  // run-time checks on (see DESIGN.md, Toolchain facts), and setQ realises everything a position stage
  // holds. For loops that need nothing but A(q) v, such as syn-evaluate's Monte-Carlo reconstructions;
  // the model tests hold it to calcMassTimes.
  void calcMassTimesAt(const Eigen::VectorXd& q, const Eigen::VectorXd& v, Eigen::VectorXd& out);
  // The same pass with accelerations: momentum = A(q) u and tau = A(q) udot + b(q, u) + g(q), as
  // calcMassTimes and calcInverseDynamics give them after setQ and setU, without realising (or changing)
  // the Simbody state. Link poses at q then come from findLinkPoseAtLastDynamics.
  void calcDynamicsAt(const Eigen::VectorXd& q, const Eigen::VectorXd& u, const Eigen::VectorXd& udot,
                      Eigen::VectorXd& momentum, Eigen::VectorXd& tau);
  Eigen::Isometry3d findLinkPoseAtLastDynamics(int link) const;
  // The mass matrix A(q) itself (nu × nu), by the composite-rigid-body algorithm on the plain-number
  // tree (O(n · depth), no Simbody realisation), for factoring once per step where many products A⁻¹ x
  // are needed (stages/simulate's TreeMassFactorization). Requires setQ.
  void calcMassMatrix(Eigen::MatrixXd& mass);
  // The same from Simbody's calcM (n multiplyByM passes): the reference the tests hold it to.
  void calcMassMatrixWithSimbody(Eigen::MatrixXd& mass);
  // out = A(q)⁻¹ v in O(n) (multiplyByMInv). Requires setQ.
  void calcMassInverseTimes(const Eigen::VectorXd& v, Eigen::VectorXd& out);
  // Generalized momentum p = A(q) u. Requires setQ and setU.
  void calcMomentum(Eigen::VectorXd& p);
  // Whole-body momentum about the centre of mass, in ground: (angular, linear). Requires setQ and setU.
  Eigen::Matrix<double, 6, 1> calcCentroidalMomentum();
  // Kinetic energy ½ uᵀ A u (J). Requires setQ and setU.
  double calcKineticEnergy();
  // tau = A udot + b(q, u) + g(q): the generalized forces that produce udot
  // with gravity and no contact. Requires setQ and setU.
  void calcInverseDynamics(const Eigen::VectorXd& udot, Eigen::VectorXd& tau);
  // udot for applied generalized forces tau, gravity included, no contact:
  // A⁻¹ (tau − b − g), two O(n) operators. Requires setQ and setU.
  void calcForwardDynamics(const Eigen::VectorXd& tau, Eigen::VectorXd& udot);
  // J̇u for calcFrameJacobian's point: the frame's (angular, linear) acceleration, in ground, when
  // udot = 0 — the velocity-product term a task-space acceleration needs (Simbody
  // calcBiasForFrameJacobian, O(n)). Requires setQ and setU.
  Eigen::Matrix<double, 6, 1> calcFrameBiasAcceleration(int link, const Eigen::Vector3d& point_in_link);
  // Whole-body centre of mass (m) and its velocity. Requires setQ (and setU for the velocity).
  Eigen::Vector3d findCenterOfMass();

 private:
  struct Impl;
  Model model_;
  std::unique_ptr<Impl> impl_;
};

}  // namespace syn
