#include "stages/retarget/velocity_estimation.h"

#include "common/configuration_space.h"

namespace syn {

void EstimateVelocities(const Model& model, const std::vector<double>& time_s, const std::vector<double>& q,
                        std::vector<double>& u, std::vector<double>& udot) {
  const size_t frames = time_s.size();
  const size_t nq = static_cast<size_t>(model.nq()), nu = static_cast<size_t>(model.nu());
  u.assign(frames * nu, 0.0);
  udot.assign(frames * nu, 0.0);
  if (frames < 2) return;
  const ConfigurationShape shape = ConfigurationShape::Of(model.hasFreeBase(), model.nq());
  for (size_t t = 0; t < frames; ++t) {
    const size_t before = t == 0 ? 0 : t - 1;
    const size_t after = t + 1 == frames ? t : t + 1;
    const double span = time_s[after] - time_s[before];
    double* velocity = &u[t * nu];
    Difference(shape, &q[before * nq], &q[after * nq], velocity);
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
