#include "stages/simulate/fixed_step_integrator.h"

#include "common/error.h"

namespace syn {

std::string_view IntegratorName(Integrator integrator) {
  return integrator == Integrator::kRungeKutta4 ? "rk4" : "euler";
}

FixedStepIntegrator::FixedStepIntegrator(const Model& model)
    : free_base_(model.hasFreeBase()), nq_(model.nq()), nu_(model.nu()) {
  q_stage_.resize(nq_);
  u_stage_.resize(nu_);
  for (int i = 0; i < 4; ++i) qdot_[i].resize(nq_), udot_[i].resize(nu_);
}

void FixedStepIntegrator::calcQDot(const Eigen::VectorXd& q, const Eigen::VectorXd& u, Eigen::VectorXd& qdot) const {
  qdot.resize(nq_);
  if (!free_base_) {
    qdot = u;
    return;
  }
  // Quaternion (w, x, y, z) of the base in ground, ω in ground: q̇ = ½ (0, ω) ⊗ q.
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  const double wx = u[0], wy = u[1], wz = u[2];
  qdot[0] = 0.5 * (-wx * x - wy * y - wz * z);
  qdot[1] = 0.5 * (wx * w + wy * z - wz * y);
  qdot[2] = 0.5 * (wy * w + wz * x - wx * z);
  qdot[3] = 0.5 * (wz * w + wx * y - wy * x);
  qdot.segment<3>(4) = u.segment<3>(3);
  qdot.tail(nq_ - 7) = u.tail(nu_ - 6);
}

void FixedStepIntegrator::evaluate(Workspace& workspace, const Eigen::VectorXd& tau, const Eigen::VectorXd& q,
                                   const Eigen::VectorXd& u, Eigen::VectorXd& qdot, Eigen::VectorXd& udot) {
  workspace.setQ(q);
  workspace.setU(u);
  workspace.calcForwardDynamics(tau, udot);
  calcQDot(q, u, qdot);
}

void FixedStepIntegrator::step(Workspace& workspace, Integrator integrator, const Eigen::VectorXd& tau, double dt,
                               const Eigen::VectorXd* udot_now, Eigen::VectorXd& q, Eigen::VectorXd& u) {
  if (integrator == Integrator::kSemiImplicitEuler) {
    if (udot_now != nullptr) {
      udot_[0] = *udot_now;
    } else {
      workspace.setQ(q);
      workspace.setU(u);
      workspace.calcForwardDynamics(tau, udot_[0]);
    }
    u.noalias() += dt * udot_[0];
    calcQDot(q, u, qdot_[0]);
    q.noalias() += dt * qdot_[0];
  } else {
    if (udot_now != nullptr) {
      udot_[0] = *udot_now;
      calcQDot(q, u, qdot_[0]);
    } else {
      evaluate(workspace, tau, q, u, qdot_[0], udot_[0]);
    }
    q_stage_ = q + 0.5 * dt * qdot_[0];
    u_stage_ = u + 0.5 * dt * udot_[0];
    evaluate(workspace, tau, q_stage_, u_stage_, qdot_[1], udot_[1]);
    q_stage_ = q + 0.5 * dt * qdot_[1];
    u_stage_ = u + 0.5 * dt * udot_[1];
    evaluate(workspace, tau, q_stage_, u_stage_, qdot_[2], udot_[2]);
    q_stage_ = q + dt * qdot_[2];
    u_stage_ = u + dt * udot_[2];
    evaluate(workspace, tau, q_stage_, u_stage_, qdot_[3], udot_[3]);
    q.noalias() += (dt / 6.0) * (qdot_[0] + 2.0 * qdot_[1] + 2.0 * qdot_[2] + qdot_[3]);
    u.noalias() += (dt / 6.0) * (udot_[0] + 2.0 * udot_[1] + 2.0 * udot_[2] + udot_[3]);
  }
  if (free_base_) q.head<4>().normalize();
}

}  // namespace syn
