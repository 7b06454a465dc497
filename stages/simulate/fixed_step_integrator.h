// Fixed-step time integration of the robot's rigid-body dynamics A(q) udot + b(q, u) + g(q) = tau with
// tau held constant over the step (the controller's zero-order hold). Deterministic: no adaptive step,
// no error control, the same inputs give the same bits.
//
//   semi-implicit Euler: u⁺ = u + h udot(q, u),  q⁺ = q + h q̇(q, u⁺) — one dynamics evaluation a step;
//                        symplectic, its energy error stays bounded but is O(h).
//   RK4:                 the classical fourth-order Runge–Kutta on (q, u) — four evaluations, energy
//                        error O(h⁴) (the test holds it to 1e-6 relative over 1 s at 1 kHz).
//
// q̇(q, u): joints q̇ = u; a free base's position q̇ = v (ground) and quaternion q̇ = ½ (0, ω) ⊗ q with ω in
// ground; the quaternion is renormalised after each step.
#pragma once

#include <string>
#include <string_view>

#include <Eigen/Core>

#include "common/model.h"

namespace syn {

enum class Integrator { kSemiImplicitEuler, kRungeKutta4 };

[[nodiscard]] std::string_view IntegratorName(Integrator integrator);  // "euler", "rk4"

class FixedStepIntegrator {
 public:
  explicit FixedStepIntegrator(const Model& model);

  // q̇ for (q, u).
  void calcQDot(const Eigen::VectorXd& q, const Eigen::VectorXd& u, Eigen::VectorXd& qdot) const;

  // Advances (q, u) by dt under the generalized forces tau (gravity comes from the model). `udot_now`
  // is udot at (q, u) when the caller already has it (the first evaluation of either method), else
  // nullptr. Leaves `workspace` at some intermediate state: call setQ/setU before using it again.
  void step(Workspace& workspace, Integrator integrator, const Eigen::VectorXd& tau, double dt,
            const Eigen::VectorXd* udot_now, Eigen::VectorXd& q, Eigen::VectorXd& u);

 private:
  bool free_base_;
  int nq_, nu_;
  Eigen::VectorXd q_stage_, u_stage_, qdot_[4], udot_[4];
  void evaluate(Workspace& workspace, const Eigen::VectorXd& tau, const Eigen::VectorXd& q, const Eigen::VectorXd& u,
                Eigen::VectorXd& qdot, Eigen::VectorXd& udot);
};

}  // namespace syn
