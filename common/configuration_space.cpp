#include "common/configuration_space.h"

#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Geometry>

namespace syn {

void Integrate(const ConfigurationShape& shape, const double* q0, const double* v, double* q1) {
  int q_joint = 0, v_joint = 0;
  if (shape.free_base) {
    const Eigen::Vector3d rotation(v[0], v[1], v[2]);
    const double angle = rotation.norm();
    const Eigen::Quaterniond step =
        angle > 0 ? Eigen::Quaterniond(Eigen::AngleAxisd(angle, rotation / angle)) : Eigen::Quaterniond::Identity();
    const Eigen::Quaterniond base = (step * Eigen::Quaterniond(q0[0], q0[1], q0[2], q0[3])).normalized();
    q1[0] = base.w(), q1[1] = base.x(), q1[2] = base.y(), q1[3] = base.z();
    for (int i = 0; i < 3; ++i) q1[4 + i] = q0[4 + i] + v[3 + i];
    q_joint = 7;
    v_joint = 6;
  }
  for (int i = 0; q_joint + i < shape.nq; ++i) q1[q_joint + i] = q0[q_joint + i] + v[v_joint + i];
}

void Difference(const ConfigurationShape& shape, const double* q0, const double* q1, double* v) {
  int q_joint = 0, v_joint = 0;
  if (shape.free_base) {
    const Eigen::Quaterniond a(q0[0], q0[1], q0[2], q0[3]);
    const Eigen::Quaterniond b(q1[0], q1[1], q1[2], q1[3]);
    const Eigen::AngleAxisd rotation(b.normalized() * a.normalized().conjugate());
    const Eigen::Vector3d angular = rotation.angle() * rotation.axis();
    for (int i = 0; i < 3; ++i) v[i] = angular[i];
    for (int i = 0; i < 3; ++i) v[3 + i] = q1[4 + i] - q0[4 + i];
    q_joint = 7;
    v_joint = 6;
  }
  for (int i = 0; q_joint + i < shape.nq; ++i) v[v_joint + i] = q1[q_joint + i] - q0[q_joint + i];
}

void InterpolateUnnormalized(const ConfigurationShape& shape, const double* q0, const double* q1, double s,
                             double* q) {
  for (int i = 0; i < shape.nq; ++i) q[i] = (1 - s) * q0[i] + s * q1[i];
  if (!shape.free_base) return;
  // The base orientation toward the nearer of q1 and −q1 (the same rotation), so the chord does not pass
  // near zero.
  if (q0[0] * q1[0] + q0[1] * q1[1] + q0[2] * q1[2] + q0[3] * q1[3] < 0) {
    for (int i = 0; i < 4; ++i) q[i] = (1 - s) * q0[i] - s * q1[i];
  }
}

void Interpolate(const ConfigurationShape& shape, const double* q0, const double* q1, double s, double* q) {
  // Normalised lerp: between neighbouring frames it is slerp to second order in the angle, and costs no
  // trigonometry.
  InterpolateUnnormalized(shape, q0, q1, s, q);
  if (!shape.free_base) return;
  const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  if (norm > 0) {
    for (int i = 0; i < 4; ++i) q[i] /= norm;
  }
}

void CheckSize(const char* what, Eigen::Index expected, Eigen::Index size) {
  if (size != expected) {
    throw std::invalid_argument(std::string(what) + ": expected " + std::to_string(expected) + " values, got " +
                                std::to_string(size));
  }
}

void Integrate(const ConfigurationShape& shape, const Eigen::VectorXd& q0, const Eigen::VectorXd& v, Eigen::VectorXd& q1) {
  CheckSize("Integrate: q0", shape.nq, q0.size());
  CheckSize("Integrate: v", shape.nu, v.size());
  q1.resize(shape.nq);
  Integrate(shape, q0.data(), v.data(), q1.data());
}

void Difference(const ConfigurationShape& shape, const Eigen::VectorXd& q0, const Eigen::VectorXd& q1, Eigen::VectorXd& v) {
  CheckSize("Difference: q0", shape.nq, q0.size());
  CheckSize("Difference: q1", shape.nq, q1.size());
  v.resize(shape.nu);
  Difference(shape, q0.data(), q1.data(), v.data());
}

void Interpolate(const ConfigurationShape& shape, const Eigen::VectorXd& q0, const Eigen::VectorXd& q1, double s,
                 Eigen::VectorXd& q) {
  CheckSize("Interpolate: q0", shape.nq, q0.size());
  CheckSize("Interpolate: q1", shape.nq, q1.size());
  q.resize(shape.nq);
  Interpolate(shape, q0.data(), q1.data(), s, q.data());
}

Eigen::Matrix3d CrossMatrix(const Eigen::Vector3d& v) {
  Eigen::Matrix3d m;
  m << 0, -v.z(), v.y(), v.z(), 0, -v.x(), -v.y(), v.x(), 0;
  return m;
}

Eigen::Matrix3d RotationLeftJacobian(const Eigen::Vector3d& phi) {
  const double angle = phi.norm();
  const Eigen::Matrix3d cross = CrossMatrix(phi);
  if (!(angle > 1e-6)) return Eigen::Matrix3d::Identity() + 0.5 * cross;  // the series' first terms
  return Eigen::Matrix3d::Identity() + (1.0 - std::cos(angle)) / (angle * angle) * cross +
         (angle - std::sin(angle)) / (angle * angle * angle) * cross * cross;
}

Eigen::Matrix3d RotationLeftJacobianInverse(const Eigen::Vector3d& phi) {
  const double angle = phi.norm();
  const Eigen::Matrix3d cross = CrossMatrix(phi);
  // 1/θ² − (1 + cos θ)/(2 θ sin θ); below 1e-3 rad its series 1/12 + θ²/720 (the closed form cancels).
  const double c = angle < 1e-3 ? 1.0 / 12.0 + angle * angle / 720.0
                                : 1.0 / (angle * angle) - (1.0 + std::cos(angle)) / (2.0 * angle * std::sin(angle));
  return Eigen::Matrix3d::Identity() - 0.5 * cross + c * cross * cross;
}

}  // namespace syn
