// `--contact ground`: the controller's generalized forces made realisable with an unactuated base.
//
// The task hierarchy plans accelerations u̇* for every velocity, the free base's six included (what the
// paper's driven base applies). On the ground nothing drives the base: its six rows of the equations of
// motion, A_b u̇ + (b + g)_b = (Σ J_pᵀ f_p)_b, must be met by sole-point forces f_p inside the friction
// cones. So:
//  1. the sole forces: the wrench about the centre of mass the plan needs is fitted by forces inside their
//     cones (ContactForceSplit, the non-negative least-squares fit syn-retarget uses for the base residual:
//     unilateral normal force, μ = 0.8 pyramid, each foot's centre of pressure inside its sole); where they
//     explain all of it the plan is realisable as it is;
//  2. the accelerations: the ones nearest the plan that the base's rows allow with those forces,
//       min ½ ‖u̇ − u̇*‖²_A + ½ w ‖J_s u̇ − a_s‖²   subject to   W(u̇) = the fitted wrench,
//     J_s, a_s the held feet's rows (StanceFeet): whatever the soles cannot give is taken up by the body
//     moving over feet that stay where the plan holds them;
//  3. the joint torques of floating-base inverse dynamics with those forces, τ = A u̇ + b + g − Σ J_pᵀ f_p
//     (τ_b = 0 by construction), clipped to the URDF's effort.
// Before (until 2026-11-28) the joints kept their planned accelerations and the base alone took the
// difference: the base turned, the held feet with it, and a held G1 sole sat more than 3° off flat (on an
// edge or a corner, its support a line or a point) in 66-89 % of its steps on six CMU walks; with the
// feet's rows kept, 13-65 % (w = 10⁴; 10³: 33-63 %, 10⁵: 17-63 %). With the planned forces also allowed
// on sole points up to 2 cm above the floor (simulation.cpp) the joints-kept version pressed tilted soles
// flat by forces where they did not touch yet, and they slapped the floor with up to 13 kN; this one
// brings them down at the held feet's own rate.
//
// The sole points that may push: within `max_height` of the floor (syn-simulate: 2 cm), on a foot the
// source plants or slower than 0.5 m/s (ContactForceOptions).
#pragma once

#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "common/contact_forces.h"
#include "common/model.h"
#include "common/robot_map.h"

namespace syn {

struct ContactConsistentOptions {
  // The held feet's rows against the accelerations' kinetic-energy metric A (kg·m² per (rad/s²)²-ish: a
  // G1's legs weigh 0.1-1, its base 35 along its translations).
  double stance_weight = 1e4;
  // Where no admissible sole forces give the whole wrench the plan needs, the fit trades its components
  // against each other: this weighs the three moments (N·m, about the centre of mass) against the force
  // (N). At 1, one to one (a moment's error counts as a force's at 1 m), as syn-retarget splits. What the
  // fit leaves out the body's accelerations absorb: a force as the centre of mass falling behind the balance
  // plan, which the capture point's feedback and stepping then correct; a moment as the whole body turning.
  // 16 runs of the 21 CMU walks onto G1 with the balance gain moved by 1-8 × 10⁻⁹ (session 35; mean walks
  // up, and CMU 07_12, the brisk walk, up in how many runs): 1: 15.81, 07_12 in 1; 2: 15.75, in 15;
  // 3: 14.81, in 16. The tilting moments alone at 1.5 / 2 / 3: 15.56 / 15.44 / 15.00, 07_12 in 10 / 16 / 14.
  // Session 48, 8 runs (the same 8 at the defaults: 17.00): fitted in step 2's own metric
  // (P H⁻¹ Pᵀ)⁻¹, which makes steps 1 and 2 one least-squares problem and weighs the moments 10-60 times
  // the force: 14.88 (mixed half and half with these weights: 15.25); the base's rows added to H, so
  // that the base turns or translates off the plan less: 15.25-15.88 (its yaw alone at 10 / 100: 16.38 /
  // 16.12, the brisk walk 07_12 down in all 8: its pelvis turning ±25° is where its legs' yaw goes); the
  // yaw moment alone at 3 / 0.3: 15.50 / 15.38; the planned μ 0.6 / 0.5 under the floor's 0.8: 16.38 /
  // 15.62; forces planned 1 / 2 cm inside the soles' corners (a margin for the centre of pressure): 17.12 /
  // 16.38.
  double moment_weight = 1.0;
};

class ContactConsistentTorques {
 public:
  // effort_limits false: no clipping (syn-simulate --no-effort-limits).
  ContactConsistentTorques(const Model& model, const std::vector<RobotFoot>& feet, const ContactForceOptions& options,
                           bool effort_limits, const ContactConsistentOptions& consistent = {});

  // At the workspace's state (setQ, setU done), with A = `mass`, b + g = `bias`, the planned accelerations
  // `planned_udot` (nu), the source's contact flags `planted` [feet] and the held feet's rows
  // (`stance_jacobian` u̇ = `stance_acceleration`, no rows when none is held): the joint torques to apply,
  // `tau` (nu; the base's entries zero, clipped to the URDF's effort). Returns the number of joints clipped.
  int apply(Workspace& workspace, const Eigen::MatrixXd& mass, const Eigen::VectorXd& bias, const Eigen::VectorXd& planned_udot,
            const int64_t* planted, const Eigen::MatrixXd& stance_jacobian, const Eigen::VectorXd& stance_acceleration,
            Eigen::VectorXd& tau);

  // After apply: the planned forces and the base wrench they leave unexplained.
  const ContactForceFrame& planned() const { return planned_; }

 private:
  ContactForceSplit split_;
  ContactConsistentOptions options_;
  Eigen::Matrix<double, 6, 1> fit_row_weights_;  // (moments, force) of the wrench fit
  std::vector<int> foot_links_;
  std::vector<int> point_foot_;
  std::vector<Eigen::Vector3d> point_local_;
  Eigen::VectorXd effort_limit_;
  std::vector<int> unactuated_;
  ContactForceFrame planned_;
  Eigen::Matrix<double, 6, Eigen::Dynamic> jacobian_;
  Eigen::MatrixXd hessian_;                 // H = A + w J_sᵀ J_s
  Eigen::LDLT<Eigen::MatrixXd> hessian_solver_;  // sized by its first compute (a copy of a sized, uncomputed LDLT reads an unset status: UBSan)
  Eigen::VectorXd gradient_, free_udot_, udot_, sole_forces_;
  Eigen::MatrixXd base_rows_;               // A_b: the base's rows of A
  Eigen::MatrixXd wrench_rows_;             // P = X A_b: W(u̇) = P u̇ + X (b + g)_b
  Eigen::MatrixXd response_;                // H⁻¹ Pᵀ
};

}  // namespace syn
