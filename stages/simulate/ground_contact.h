// Compliant contact between the robot map's sole points and the ground plane z = 0, for syn-simulate's
// `--contact ground`.
//
// Normal: Hunt and Crossley's force f_n = k δ^1.5 (1 + 1.5 c δ̇) on each sole point δ below the plane
// (never pulling, within the implicit step too: releasePullingPoints), the model Simbody's
// HuntCrossleyForce uses for sphere–half-space contact. Tangential:
// an elastic stick–slip anchor per point (a bristle): a point that touches down is anchored where it
// lands and pulled back by k_t (anchor − p) − b_t v, and where that exceeds μ f_n the anchor slides so
// the force stays on the friction cone. Unlike a regularised Coulomb law (−μ f_n v / max(|v|, v_s)) a
// standing foot does not creep.
//
// Stiffness: G1's 35 kg on both feet' eight points sinks each about 0.8 mm at k = 2·10⁶ N/m^1.5; the
// contact's natural frequency (about 140 rad/s) stays well inside what a 1 kHz semi-implicit Euler step
// resolves (ω h ≈ 0.14).
//
// Dissipation: c = 1 s/m, a restitution of about 0.3 at a 1 m/s touchdown (rubber on a hard floor). At
// 10 s/m a point leaving the floor faster than 1/(1.5 c) = 0.07 m/s carried no force however deep it was,
// the linearly implicit step overshot that kink, and a standing sole's force switched between 0 and
// 20-43 kN every step with the sole 13 mm deep (CMU 02_02 onto G1 in ground mode); at 1 s/m the walks'
// peak vertical force is 1.9-4.5 body weights and their soles at most 4.5 mm deep.
#pragma once

#include <vector>

#include <Eigen/Core>
#include <Eigen/LU>

#include "common/model.h"
#include "common/robot_map.h"

namespace syn {

struct GroundContactOptions {
  double stiffness = 2e6;            // k, N/m^1.5 per sole point
  double dissipation = 1.0;          // c, s/m (Hunt–Crossley; see above)
  double friction = 0.8;             // μ, the default
  double tangential_stiffness = 1e5;  // k_t, N/m per point
  double tangential_damping = 600;   // b_t, N·s/m per point
};

class GroundContact {
 public:
  GroundContact(const Model& model, const std::vector<RobotFoot>& feet, const GroundContactOptions& options);

  // The contact forces at the workspace's state (setQ, setU done): `generalized` (nu) = Σ J_pᵀ f_p. Moves
  // the friction anchors: call once per step.
  // Also the forces' stiffness and damping in generalized coordinates, K = Σ J_pᵀ K_p J_p and
  // B = Σ J_pᵀ B_p J_p (K_p, B_p: −∂f_p/∂p and −∂f_p/∂ṗ of a touching point), for a linearly implicit
  // step: a 0.6 kg foot on a 10⁵ N·s/m Hunt–Crossley damper is unstable for any explicit 1 ms step.
  void calcForces(Workspace& workspace, Eigen::VectorXd& generalized, Eigen::MatrixXd& stiffness,
                  Eigen::MatrixXd& damping);

  // Per foot, the force the linearly implicit step applies once it has solved u̇ (h the step):
  // f − K h (u + h u̇) − B h u̇ over the last call's touching points (N, ground). This, not f at the step's
  // start, is what acted: a sole point coming down at 2.7 m/s evaluates to 5 kN at the step's start, which
  // the implicit terms take back (CMU 07_06 onto G1: 20.6 kN evaluated, 1.6 kN applied in the same step).
  const std::vector<Eigen::Vector3d>& appliedFootForce(const Eigen::VectorXd& u, const Eigen::VectorXd& udot, double h);

  // The floor never pulls, not even inside the implicit step. calcForces's normal force is a tangent at the
  // step's start; a sole point yanked off the floor (a swing's start: 800 m/s² at its points) or bouncing
  // off it within the step (a 2.6 m/s touchdown) crosses f_n = 0 during the step and the tangent runs on
  // below zero: before this (session 41) the floor held feet down by up to 98 N at a recorded frame on 15
  // of the 21 CMU walks onto G1, in 1 % of their recorded frames. So, after the step's solve:
  //  1. releasePullingPoints: every touching point whose applied normal force (appliedFootForce's) is below
  //     zero is taken out of the sums (`generalized`, `stiffness`, `damping` as calcForces left them, with
  //     whatever else the caller added). Returns how many; none: the step stands.
  //  2. the caller solves the step without them, and
  //  3. releasedForces gives the released points what Hunt–Crossley gives at the end state they reach with
  //     it: constant normal forces F ≥ 0 with F_p = f_n(depth_p − h v_p(F), v_p(F)), v_p the point's end
  //     velocity, linear in F through `response` (the step's solve: response(r, out) sets out = u̇ for the
  //     generalized force r). A point leaving the floor gets nothing; one landing hard the force that stops
  //     it no more than the floor does (released outright it fell through the floor for the step: soles
  //     26 mm deep on CMU walks). Their friction is calcForces's, kept inside μ F_p, a constant force too
  //     (it is left out of the normal forces' solve). Returns their generalized force Σ J_pᵀ f_p, to add to
  //     the step's and solve again.
  int releasePullingPoints(const Eigen::VectorXd& u, const Eigen::VectorXd& udot, double h, Eigen::VectorXd& generalized,
                           Eigen::MatrixXd& stiffness, Eigen::MatrixXd& damping);
  template <typename Response>
  const Eigen::VectorXd& releasedForces(const Eigen::VectorXd& u, const Eigen::VectorXd& udot, double h, const Response& response);
  // The deepest sole point below z = 0 at the last call (m, ≥ 0).
  double deepestPenetration() const { return deepest_; }
  // Per foot, whether any of its points touched at the last call.
  bool footTouches(size_t foot) const { return foot_touches_[foot]; }

 private:
  struct SolePoint {
    int foot;
    Eigen::Vector3d local;   // in the foot link's frame
    bool anchored = false;
    Eigen::Vector2d anchor = Eigen::Vector2d::Zero();  // ground x, y
    // At the last call, if it touched: its force, −∂f/∂p and −∂f/∂ṗ (diagonal), and its Jacobian's rows.
    bool touching = false;
    Eigen::Vector3d force = Eigen::Vector3d::Zero(), stiffness = Eigen::Vector3d::Zero(), damping = Eigen::Vector3d::Zero();
    Eigen::Matrix<double, 3, Eigen::Dynamic> jacobian;
    double depth = 0;        // below the plane at the step's start (m)
    bool released = false;   // this step: its force is the constant `released_applied` (N), normal `released_force`
    double released_force = 0;
    Eigen::Vector3d released_applied = Eigen::Vector3d::Zero();
  };
  // The force a touching point applies over the step once u̇ is solved (see appliedFootForce).
  [[nodiscard]] static Eigen::Vector3d AppliedForce(const SolePoint& point, const Eigen::VectorXd& u, const Eigen::VectorXd& udot,
                                                    double h);
  // A released point's force: its normal force, and the friction calcForces gave it kept inside μ times that.
  [[nodiscard]] Eigen::Vector3d ReleasedForce(const SolePoint& point) const;
  // Hunt–Crossley's normal force at `depth` (m) and normal velocity `rising` (m/s, up); 0 off the floor.
  [[nodiscard]] double NormalForce(double depth, double rising) const;
  // releasedForces's consistent forces, given each released point's end velocity without them
  // (`free_rising`) and R, their end velocities per unit force of each (released_response_).
  void SolveReleasedForces(double h);
  GroundContactOptions options_;
  std::vector<int> foot_links_;
  std::vector<SolePoint> points_;
  std::vector<Eigen::Vector3d> applied_force_;
  std::vector<bool> foot_touches_;
  double deepest_ = 0;
  Eigen::Matrix<double, 6, Eigen::Dynamic> jacobian_;
  // The released points' solve, in storage of a fixed largest size: no allocation per step.
  static constexpr int kMaxSolePoints = 32;
  using SmallVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxSolePoints, 1>;
  using SmallMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxSolePoints, kMaxSolePoints>;
  std::vector<int> released_;
  SmallVector free_rising_, released_solution_, released_residual_;
  SmallMatrix released_response_;  // R(i, j): point i's end velocity (up) per newton at point j
  SmallMatrix released_newton_;
  Eigen::PartialPivLU<SmallMatrix> released_lu_;
  Eigen::VectorXd released_generalized_, unit_force_, unit_response_;
};

template <typename Response>
const Eigen::VectorXd& GroundContact::releasedForces(const Eigen::VectorXd& u, const Eigen::VectorXd& udot, double h,
                                                     const Response& response) {
  const Eigen::Index n = static_cast<Eigen::Index>(released_.size());
  free_rising_.resize(n);
  released_response_.resize(n, n);
  released_solution_.resize(n);
  released_residual_.resize(n);
  released_newton_.resize(n, n);
  released_generalized_.setZero(u.size());
  unit_force_.resize(u.size());
  unit_response_.resize(u.size());
  for (Eigen::Index j = 0; j < n; ++j) {
    const SolePoint& point = points_[static_cast<size_t>(released_[static_cast<size_t>(j)])];
    free_rising_[j] = point.jacobian.row(2).dot(u) + h * point.jacobian.row(2).dot(udot);
    unit_force_ = point.jacobian.row(2).transpose();
    response(unit_force_, unit_response_);
    for (Eigen::Index i = 0; i < n; ++i) {
      released_response_(i, j) = h * points_[static_cast<size_t>(released_[static_cast<size_t>(i)])].jacobian.row(2).dot(unit_response_);
    }
  }
  SolveReleasedForces(h);
  for (int p : released_) {
    SolePoint& point = points_[static_cast<size_t>(p)];
    released_generalized_.noalias() += point.jacobian.transpose() * ReleasedForce(point);
  }
  return released_generalized_;
}

}  // namespace syn
