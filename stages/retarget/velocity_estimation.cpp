#include "stages/retarget/velocity_estimation.h"

#include <Eigen/Geometry>

namespace syn {
namespace {

// Velocity-space difference (q_b ⊖ q_a), size nu.
void Difference(const Model& model, const double* q_a, const double* q_b, double* out) {
  const int nq = model.nq(), nu = model.nu();
  if (!model.hasFreeBase()) {
    for (int i = 0; i < nq; ++i) out[i] = q_b[i] - q_a[i];
    return;
  }
  const Eigen::Quaterniond a(q_a[0], q_a[1], q_a[2], q_a[3]);
  const Eigen::Quaterniond b(q_b[0], q_b[1], q_b[2], q_b[3]);
  const Eigen::AngleAxisd rotation(b.normalized() * a.normalized().conjugate());
  const Eigen::Vector3d angular = rotation.angle() * rotation.axis();
  for (int i = 0; i < 3; ++i) out[i] = angular[i];
  for (int i = 0; i < 3; ++i) out[3 + i] = q_b[4 + i] - q_a[4 + i];
  for (int i = 6; i < nu; ++i) out[i] = q_b[i + 1] - q_a[i + 1];
}

}  // namespace

void EstimateVelocities(const Model& model, const std::vector<double>& time_s, const std::vector<double>& q,
                        std::vector<double>& u, std::vector<double>& udot) {
  const size_t frames = time_s.size();
  const size_t nq = static_cast<size_t>(model.nq()), nu = static_cast<size_t>(model.nu());
  u.assign(frames * nu, 0.0);
  udot.assign(frames * nu, 0.0);
  if (frames < 2) return;
  for (size_t t = 0; t < frames; ++t) {
    const size_t before = t == 0 ? 0 : t - 1;
    const size_t after = t + 1 == frames ? t : t + 1;
    const double span = time_s[after] - time_s[before];
    double* velocity = &u[t * nu];
    Difference(model, &q[before * nq], &q[after * nq], velocity);
    for (size_t i = 0; i < nu; ++i) velocity[i] /= span;
  }
  for (size_t t = 0; t < frames; ++t) {
    const size_t before = t == 0 ? 0 : t - 1;
    const size_t after = t + 1 == frames ? t : t + 1;
    const double span = time_s[after] - time_s[before];
    for (size_t i = 0; i < nu; ++i) udot[t * nu + i] = (u[after * nu + i] - u[before * nu + i]) / span;
  }
}

}  // namespace syn
