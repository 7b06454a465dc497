#include "stages/project/torso_null_space.h"

#include <Eigen/LU>

namespace syn {

TorsoNullSpace::TorsoNullSpace(const Model& model, int torso_link)
    : workspace_(model), link_(torso_link), frame_jacobian_(6, model.nu()), jacobian_(3, model.nu()),
      minv_jt_(model.nu(), 3), column_(model.nu()), product_(model.nu()) {}

void TorsoNullSpace::setConfiguration(const Eigen::VectorXd& q) {
  workspace_.setQ(q);
  workspace_.calcFrameJacobian(link_, Eigen::Vector3d::Zero(), frame_jacobian_);
  jacobian_ = frame_jacobian_.topRows<3>();
  for (int axis = 0; axis < 3; ++axis) {
    column_ = jacobian_.row(axis).transpose();
    workspace_.calcMassInverseTimes(column_, product_);
    minv_jt_.col(axis) = product_;
  }
  lambda_ = (jacobian_ * minv_jt_).inverse();
}

void TorsoNullSpace::applyTaskSpace(const Eigen::VectorXd& u, Eigen::VectorXd& out) const {
  const Eigen::Vector3d task_velocity = jacobian_ * u;
  out.noalias() = minv_jt_ * (lambda_ * task_velocity);
}

void TorsoNullSpace::applyNullSpace(const Eigen::VectorXd& u, Eigen::VectorXd& out) const {
  applyTaskSpace(u, out);
  out = u - out;
}

}  // namespace syn
