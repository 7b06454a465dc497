#include "stages/simulate/ground_contact.h"

#include <algorithm>
#include <cmath>
#include <utility>

namespace syn {

GroundContact::GroundContact(const Model& model, const std::vector<RobotFoot>& feet, const GroundContactOptions& options)
    : options_(options), applied_force_(feet.size()), foot_touches_(feet.size(), false) {
  for (size_t f = 0; f < feet.size(); ++f) {
    foot_links_.push_back(model.findLinkIndex(feet[f].link));
    for (const std::array<double, 3>& local : feet[f].sole_points) {
      SolePoint point;
      point.foot = static_cast<int>(f);
      point.local = Eigen::Vector3d(local[0], local[1], local[2]);
      point.jacobian.setZero(3, model.nu());
      points_.push_back(std::move(point));
    }
  }
  jacobian_.resize(6, model.nu());
}

void GroundContact::calcForces(Workspace& workspace, Eigen::VectorXd& generalized, Eigen::MatrixXd& stiffness,
                               Eigen::MatrixXd& damping) {
  const int nu = workspace.model().nu();
  generalized.setZero(nu);
  stiffness.setZero(nu, nu);
  damping.setZero(nu, nu);
  std::fill(foot_touches_.begin(), foot_touches_.end(), false);
  deepest_ = 0;
  const Eigen::VectorXd& u = workspace.getU();
  for (SolePoint& point : points_) {
    const int link = foot_links_[static_cast<size_t>(point.foot)];
    const Eigen::Vector3d position = workspace.findLinkPose(link) * point.local;
    const double depth = -position.z();
    point.touching = depth > 0;
    if (!point.touching) {
      point.anchored = false;  // lifted: the next touchdown anchors afresh
      continue;
    }
    workspace.calcFrameJacobian(link, point.local, jacobian_);
    const Eigen::Vector3d velocity = jacobian_.bottomRows<3>() * u;
    const double normal = std::max(0.0, options_.stiffness * std::pow(depth, 1.5) * (1.0 - 1.5 * options_.dissipation * velocity.z()));
    if (!point.anchored) point.anchor = position.head<2>(), point.anchored = true;
    Eigen::Vector2d tangential = options_.tangential_stiffness * (point.anchor - position.head<2>()) -
                                 options_.tangential_damping * velocity.head<2>();
    const double limit = options_.friction * normal;
    const bool sliding = tangential.norm() > limit;
    if (sliding) {
      // Sliding: the force on the cone, and the anchor moved to where the spring alone gives it.
      tangential *= limit / tangential.norm();
      point.anchor = position.head<2>() + tangential / options_.tangential_stiffness;
    }
    // −∂f/∂p and −∂f/∂ṗ of this point (a sliding point's tangential force follows the normal one; its
    // own derivatives are left out).
    const double hc = 1.0 - 1.5 * options_.dissipation * velocity.z();
    const Eigen::Vector3d point_stiffness(sliding ? 0.0 : options_.tangential_stiffness, sliding ? 0.0 : options_.tangential_stiffness,
                                          normal > 0 ? 1.5 * options_.stiffness * std::sqrt(depth) * hc : 0.0);
    const Eigen::Vector3d point_damping(sliding ? 0.0 : options_.tangential_damping, sliding ? 0.0 : options_.tangential_damping,
                                        normal > 0 ? 1.5 * options_.dissipation * options_.stiffness * std::pow(depth, 1.5) : 0.0);
    stiffness.noalias() += jacobian_.bottomRows<3>().transpose() * point_stiffness.asDiagonal() * jacobian_.bottomRows<3>();
    damping.noalias() += jacobian_.bottomRows<3>().transpose() * point_damping.asDiagonal() * jacobian_.bottomRows<3>();
    const Eigen::Vector3d force(tangential.x(), tangential.y(), normal);
    point.force = force, point.stiffness = point_stiffness, point.damping = point_damping;
    point.jacobian = jacobian_.bottomRows<3>();
    generalized.noalias() += jacobian_.bottomRows<3>().transpose() * force;
    foot_touches_[static_cast<size_t>(point.foot)] = true;
    deepest_ = std::max(deepest_, depth);
  }
}

const std::vector<Eigen::Vector3d>& GroundContact::appliedFootForce(const Eigen::VectorXd& u, const Eigen::VectorXd& udot,
                                                                    double h) {
  for (Eigen::Vector3d& force : applied_force_) force.setZero();
  for (const SolePoint& point : points_) {
    if (!point.touching) continue;
    const Eigen::Vector3d velocity = point.jacobian * u, acceleration = point.jacobian * udot;
    applied_force_[static_cast<size_t>(point.foot)] += point.force - point.stiffness.cwiseProduct(h * (velocity + h * acceleration)) -
                                                        point.damping.cwiseProduct(h * acceleration);
  }
  return applied_force_;
}

}  // namespace syn
