#include "common/motion_integration.h"

#include <cmath>
#include <stdexcept>

#include <Eigen/Geometry>

#include "common/configuration_space.h"

namespace syn {
namespace {

constexpr int kMaxVelocities = 256;

}  // namespace

double BaseYaw(const double* quaternion_wxyz) {
  const Eigen::Quaterniond rotation(quaternion_wxyz[0], quaternion_wxyz[1], quaternion_wxyz[2], quaternion_wxyz[3]);
  const Eigen::Matrix3d matrix = rotation.normalized().toRotationMatrix();
  return std::atan2(matrix(1, 0), matrix(0, 0));
}

void MakeBaseQuaternionsContinuous(std::vector<double>& q, int64_t nq) {
  const int64_t frames = static_cast<int64_t>(q.size()) / nq;
  for (int64_t t = 1; t < frames; ++t) {
    double* now = &q[static_cast<size_t>(t * nq)];
    const double* before = now - nq;
    if (now[0] * before[0] + now[1] * before[1] + now[2] * before[2] + now[3] * before[3] < 0) {
      for (int i = 0; i < 4; ++i) now[i] = -now[i];
    }
  }
}

void RotateBaseVelocities(double yaw, double* u) {
  const double c = std::cos(yaw), s = std::sin(yaw);
  for (int block = 0; block < 2; ++block) {
    double* v = u + 3 * block;
    const double x = v[0], y = v[1];
    v[0] = c * x - s * y;
    v[1] = s * x + c * y;
  }
}

void StepConfiguration(bool free_base, const double* q0, const double* v0, const double* v1, double dt, int nq,
                       double* q1) {
  const ConfigurationShape shape = ConfigurationShape::Of(free_base, nq);
  // On the stack: this runs once per sample of every Monte-Carlo reconstruction.
  if (shape.nu > kMaxVelocities) throw std::invalid_argument("StepConfiguration: more than 256 velocities");
  Eigen::Matrix<double, Eigen::Dynamic, 1, Eigen::ColMajor, kMaxVelocities, 1> step(shape.nu);
  for (int i = 0; i < shape.nu; ++i) step[i] = 0.5 * dt * (v0[i] + v1[i]);
  Integrate(shape, q0, step.data(), q1);
}

void IntegrateVelocities(bool free_base, const Eigen::VectorXd& q0, const Eigen::VectorXd& times,
                         const Eigen::MatrixXd& velocities, BaseVelocityFrame frame, Eigen::MatrixXd& q,
                         Eigen::MatrixXd& ground_velocities) {
  const Eigen::Index frames = velocities.rows(), nu = velocities.cols(), nq = q0.size();
  if (times.size() != frames || frames < 1 || nq != nu + (free_base ? 1 : 0)) {
    throw std::invalid_argument("IntegrateVelocities: q0, times and velocities disagree in size");
  }
  // Row-major copies so that each frame is contiguous for StepConfiguration.
  Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> q_rows(frames, nq), v_rows = velocities;
  q_rows.row(0) = q0.transpose();
  const bool turn = free_base && frame == BaseVelocityFrame::kHeading;
  if (turn) RotateBaseVelocities(BaseYaw(q_rows.row(0).data()), v_rows.row(0).data());
  Eigen::VectorXd predicted(nq), heading_sample(nu);
  for (Eigen::Index t = 1; t < frames; ++t) {
    const double dt = times[t] - times[t - 1];
    double* v1 = v_rows.row(t).data();
    if (turn) {
      // Predict the pose with the previous velocity, turn the new sample with the predicted yaw, then correct.
      heading_sample = v_rows.row(t).transpose();
      StepConfiguration(true, q_rows.row(t - 1).data(), v_rows.row(t - 1).data(), v_rows.row(t - 1).data(), dt,
                        static_cast<int>(nq), predicted.data());
      RotateBaseVelocities(BaseYaw(predicted.data()), v1);
      Eigen::Map<Eigen::VectorXd> corrected(v1, nu);
      StepConfiguration(true, q_rows.row(t - 1).data(), v_rows.row(t - 1).data(), v1, dt, static_cast<int>(nq),
                        predicted.data());
      corrected = heading_sample;
      RotateBaseVelocities(BaseYaw(predicted.data()), v1);
    }
    StepConfiguration(free_base, q_rows.row(t - 1).data(), v_rows.row(t - 1).data(), v1, dt, static_cast<int>(nq),
                      q_rows.row(t).data());
  }
  q = q_rows;
  ground_velocities = v_rows;
}

}  // namespace syn
