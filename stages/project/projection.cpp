#include "stages/project/projection.h"

#include <cmath>

#include "common/cubic_spline.h"
#include "common/error.h"
#include "common/motion_from_trajectory.h"
#include "common/motion_integration.h"
#include "stages/project/torso_null_space.h"

namespace syn {
namespace {

// P v = R S Sᵀ Rᵀ v: the basis lives in the heading frame, R turns the base velocities by the frame's yaw.
class HeadingProjector {
 public:
  HeadingProjector(const Eigen::MatrixXd& basis, bool free_base)
      : basis_(basis), free_base_(free_base), turned_(basis.cols()), coefficients_(basis.rows()) {}
  void apply(double yaw, const Eigen::VectorXd& v, Eigen::VectorXd& out) {
    turned_ = v;
    if (free_base_) RotateBaseVelocities(-yaw, turned_.data());
    coefficients_.noalias() = basis_ * turned_;
    out.noalias() = basis_.transpose() * coefficients_;
    if (free_base_) RotateBaseVelocities(yaw, out.data());
  }

 private:
  const Eigen::MatrixXd& basis_;
  bool free_base_;
  Eigen::VectorXd turned_, coefficients_;
};

}  // namespace

ProjectionResult ProjectMotion(const MotionData& input, const Model& model, int torso_link, const Eigen::MatrixXd& basis,
                               const MotionData* torso_motion) {
  CheckMotionMatchesModel(input, model);
  const int64_t frames = input.frames(), nq = model.nq(), nu = model.nu();
  if (frames < 2) throw DataError(Location::InFile("motion"), "needs at least 2 frames to project");
  if (basis.cols() != nu) {
    throw DataError(Location::InFile("library"), "the style basis has " + std::to_string(basis.cols()) +
                                                     " velocities; " + model.name() + " has " + std::to_string(nu));
  }
  std::optional<CubicSpline> torso_velocity;
  if (torso_motion) {
    CheckMotionMatchesModel(*torso_motion, model);
    torso_velocity.emplace(torso_motion->time_s, torso_motion->u, nu);
  }
  const bool free_base = model.hasFreeBase();
  TorsoNullSpace null_space(model, torso_link);
  HeadingProjector project(basis, free_base);
  ProjectionResult result;
  Eigen::MatrixXd velocities(frames, nu);
  Eigen::VectorXd q(nq), u(nu), null_u(nu), projected(nu), source(nu), torso(nu), check(nu);
  for (int64_t t = 0; t < frames; ++t) {
    q = Eigen::Map<const Eigen::VectorXd>(&input.q[static_cast<size_t>(t * nq)], nq);
    u = Eigen::Map<const Eigen::VectorXd>(&input.u[static_cast<size_t>(t * nu)], nu);
    null_space.setConfiguration(q);
    const double yaw = free_base ? BaseYaw(q.data()) : 0.0;
    null_space.applyNullSpace(u, null_u);
    const double scale = null_space.jacobian().norm() * u.norm();
    if (scale > 0) {
      result.worst_task_leak = std::max(result.worst_task_leak, (null_space.jacobian() * null_u).norm() / scale);
    }
    project.apply(yaw, null_u, projected);
    if (torso_velocity) {
      torso_velocity->evaluate(input.time_s[static_cast<size_t>(t)], source.data(), nullptr);
    } else {
      project.apply(yaw, u, source);  // the library's own reconstruction of the input
    }
    null_space.applyTaskSpace(source, torso);
    velocities.row(t) = (projected + torso).transpose();
    project.apply(yaw, projected, check);
    if (projected.norm() > 0) {
      result.worst_subspace_residual = std::max(result.worst_subspace_residual, (projected - check).norm() / projected.norm());
    }
  }
  Eigen::MatrixXd q_hat, u_hat;
  const Eigen::VectorXd q0 = Eigen::Map<const Eigen::VectorXd>(input.q.data(), nq);
  IntegrateVelocities(free_base, q0, Eigen::Map<const Eigen::VectorXd>(input.time_s.data(), frames), velocities,
                      BaseVelocityFrame::kGround, q_hat, u_hat);
  result.motion = MotionFromTrajectory(model, input.time_s, q_hat, u_hat);
  return result;
}

}  // namespace syn
