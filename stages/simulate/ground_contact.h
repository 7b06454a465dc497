// Compliant contact between the robot map's sole points and the ground plane z = 0, for syn-simulate's
// `--contact ground`.
//
// Normal: Hunt and Crossley's force f_n = k δ^1.5 (1 + 1.5 c δ̇) on each sole point δ below the plane
// (never pulling), the model Simbody's HuntCrossleyForce uses for sphere–half-space contact. Tangential:
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
  };
  GroundContactOptions options_;
  std::vector<int> foot_links_;
  std::vector<SolePoint> points_;
  std::vector<Eigen::Vector3d> applied_force_;
  std::vector<bool> foot_touches_;
  double deepest_ = 0;
  Eigen::Matrix<double, 6, Eigen::Dynamic> jacobian_;
};

}  // namespace syn
