// `--contact ground`: the controller's generalized forces made realisable with an unactuated base.
//
// The task hierarchy plans generalized forces Γ for every velocity, the free base's six included (what
// the paper's driven base applies), i.e. accelerations a = A⁻¹ (Γ − b − g). On the ground nothing
// drives the base: its six entries must come from the soles. So they are split into sole-point forces
// f_p inside the friction cones (ContactForceSplit, the non-negative least-squares fit syn-retarget
// uses for the base residual: unilateral normal force, μ = 0.8 pyramid, each foot's centre of pressure
// inside its sole), c = Σ J_pᵀ f_p. Then floating-base inverse dynamics with those forces: the joints
// keep their planned accelerations a_j, the base gets what the forces can give,
//   a_b = A_bb⁻¹ (c_b − (b + g)_b − A_bj a_j),   τ = A a + b + g − c   (τ_b = 0 by construction).
// Where the forces explain the whole base wrench, a_b is the planned one and τ_j = Γ_j − c_j; where
// they explain nothing (a foot in flight), the joints still move as planned and the base follows
// physics. The compliant ground then pushes with what penetration gives, near f when the feet are
// down; the tasks' feedback answers the difference in the next steps, or the robot falls.
//
// The sole points that may push: within `max_height` (2 mm) of the floor, on a foot the source plants or
// slower than 0.5 m/s (ContactForceOptions).
#pragma once

#include <vector>

#include <Eigen/Cholesky>
#include <Eigen/Core>

#include "common/contact_forces.h"
#include "common/model.h"
#include "common/robot_map.h"
#include "stages/simulate/operational_space_controller.h"

namespace syn {

class ContactConsistentTorques {
 public:
  // effort_limits false: no clipping (syn-simulate --no-effort-limits).
  ContactConsistentTorques(const Model& model, const std::vector<RobotFoot>& feet, const ContactForceOptions& options,
                           bool effort_limits);

  // tau (nu, the controller's Γ + b + g, just computed by `controller` at the workspace's state) → the
  // joint torques to apply: the base's entries zero, clipped to the URDF's effort. `planted` [feet] the
  // source's contact flags at this time. Returns the number of joints clipped.
  int apply(Workspace& workspace, const OperationalSpaceController& controller, const int64_t* planted,
            Eigen::VectorXd& tau);

  // After apply: the planned forces and the base wrench they leave unexplained.
  const ContactForceFrame& planned() const { return planned_; }

 private:
  ContactForceSplit split_;
  std::vector<int> foot_links_;
  std::vector<int> point_foot_;
  std::vector<Eigen::Vector3d> point_local_;
  Eigen::VectorXd effort_limit_;
  std::vector<int> unactuated_;
  ContactForceFrame planned_;
  std::vector<int> actuated_;
  Eigen::Matrix<double, 6, Eigen::Dynamic> jacobian_;
  Eigen::VectorXd planned_udot_, sole_forces_;  // A⁻¹ (Γ − b − g) and Σ J_pᵀ f_p
  Eigen::MatrixXd base_block_;
  Eigen::LDLT<Eigen::MatrixXd> base_solver_;
  Eigen::VectorXd base_rhs_;
};

}  // namespace syn
