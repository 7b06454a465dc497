#include "stages/simulate/ground_contact.h"

#include <algorithm>
#include <cmath>
#include <string>
#include <utility>

#include "common/error.h"

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
  released_.reserve(points_.size());
  if (points_.size() > static_cast<size_t>(kMaxSolePoints)) {
    throw UsageError("the robot map has " + std::to_string(points_.size()) + " sole points; syn-simulate's ground contact takes at most " +
                    std::to_string(kMaxSolePoints));
  }
}

void GroundContact::calcForces(Workspace& workspace, Eigen::VectorXd& generalized, Eigen::MatrixXd& stiffness,
                               Eigen::MatrixXd& damping) {
  const int nu = workspace.model().nu();
  generalized.setZero(nu);
  stiffness.setZero(nu, nu);
  damping.setZero(nu, nu);
  std::fill(foot_touches_.begin(), foot_touches_.end(), false);
  released_.clear();
  deepest_ = 0;
  const Eigen::VectorXd& u = workspace.getU();
  for (SolePoint& point : points_) {
    const int link = foot_links_[static_cast<size_t>(point.foot)];
    const Eigen::Vector3d position = workspace.findLinkPose(link) * point.local;
    const double depth = -position.z();
    point.touching = depth > 0;
    point.depth = depth;
    point.released = false;
    if (!point.touching) {
      point.anchored = false;  // lifted: the next touchdown anchors afresh
      continue;
    }
    workspace.calcFrameJacobian(link, point.local, jacobian_);
    const Eigen::Vector3d velocity = jacobian_.bottomRows<3>() * u;
    const double normal = NormalForce(depth, velocity.z());
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

double GroundContact::NormalForce(double depth, double rising) const {
  const double dissipation = 1.0 - 1.5 * options_.dissipation * rising;
  return depth > 0 && dissipation > 0 ? options_.stiffness * std::pow(depth, 1.5) * dissipation : 0.0;
}

Eigen::Vector3d GroundContact::AppliedForce(const SolePoint& point, const Eigen::VectorXd& u, const Eigen::VectorXd& udot,
                                            double h) {
  if (point.released) return point.released_applied;
  const Eigen::Vector3d velocity = point.jacobian * u, acceleration = point.jacobian * udot;
  return point.force - point.stiffness.cwiseProduct(h * (velocity + h * acceleration)) - point.damping.cwiseProduct(h * acceleration);
}

const std::vector<Eigen::Vector3d>& GroundContact::appliedFootForce(const Eigen::VectorXd& u, const Eigen::VectorXd& udot,
                                                                    double h) {
  for (Eigen::Vector3d& force : applied_force_) force.setZero();
  for (const SolePoint& point : points_) {
    if (point.touching) applied_force_[static_cast<size_t>(point.foot)] += AppliedForce(point, u, udot, h);
  }
  return applied_force_;
}

int GroundContact::releasePullingPoints(const Eigen::VectorXd& u, const Eigen::VectorXd& udot, double h,
                                        Eigen::VectorXd& generalized, Eigen::MatrixXd& stiffness, Eigen::MatrixXd& damping) {
  int released = 0;
  for (size_t p = 0; p < points_.size(); ++p) {
    SolePoint& point = points_[p];
    if (!point.touching || point.released || AppliedForce(point, u, udot, h).z() >= 0) continue;
    generalized.noalias() -= point.jacobian.transpose() * point.force;
    stiffness.noalias() -= point.jacobian.transpose() * point.stiffness.asDiagonal() * point.jacobian;
    damping.noalias() -= point.jacobian.transpose() * point.damping.asDiagonal() * point.jacobian;
    point.released = true, point.released_force = 0, point.released_applied.setZero();
    released_.push_back(static_cast<int>(p));
    ++released;
  }
  return released;
}

void GroundContact::SolveReleasedForces(double h) {
  // Newton on G(F) = F − f_n(v_free + R F) = 0, projected onto F ≥ 0. f_n falls convexly as a point rises,
  // so the iterates from F = 0 approach from below. (Gauss–Seidel point by point, the first version, shrank
  // the error only by 0.7 a sweep on a landing body: its points push each other through the rigid sole.)
  const Eigen::Index n = static_cast<Eigen::Index>(released_.size());
  auto force = released_solution_.head(n);
  auto residual = released_residual_.head(n);
  auto newton = released_newton_.topLeftCorner(n, n);
  force.setZero();
  const double k = options_.stiffness, c = options_.dissipation;
  for (int iteration = 0; iteration < 50; ++iteration) {
    newton = -released_response_.topLeftCorner(n, n);
    for (Eigen::Index i = 0; i < n; ++i) {
      const SolePoint& point = points_[static_cast<size_t>(released_[static_cast<size_t>(i)])];
      const double rising = free_rising_[i] + released_response_.row(i).head(n).dot(force);
      const double depth = point.depth - h * rising, hc = 1.0 - 1.5 * c * rising;
      const double normal = NormalForce(depth, rising);
      residual[i] = force[i] - normal;
      // −∂f_n/∂v along the step's end (depth δ − h v): the Newton matrix's row is I + that times R's row.
      const double slope = normal > 0 ? h * 1.5 * k * std::sqrt(depth) * hc + 1.5 * c * k * std::pow(depth, 1.5) : 0.0;
      newton.row(i) *= -slope;
      newton(i, i) += 1.0;
    }
    if (residual.cwiseAbs().maxCoeff() <= 1e-9 * (1.0 + force.cwiseAbs().maxCoeff())) break;
    released_lu_.compute(newton);
    force -= released_lu_.solve(residual);
    force = force.cwiseMax(0.0);
  }
  for (Eigen::Index i = 0; i < n; ++i) {
    SolePoint& point = points_[static_cast<size_t>(released_[static_cast<size_t>(i)])];
    point.released_force = force[i];
    point.released_applied = ReleasedForce(point);
  }
}

Eigen::Vector3d GroundContact::ReleasedForce(const SolePoint& point) const {
  Eigen::Vector2d friction = point.force.head<2>();
  const double limit = options_.friction * point.released_force;
  if (friction.norm() > limit) friction *= limit / friction.norm();
  return Eigen::Vector3d(friction.x(), friction.y(), point.released_force);
}

}  // namespace syn
