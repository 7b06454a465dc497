// Generalized velocities and accelerations of a sampled configuration
// trajectory, by central differences in the velocity (tangent) space.
#pragma once

#include <vector>

#include "common/model.h"

namespace syn {

// q: [T, nq] row-major; fills u and udot: [T, nu]. Joints and a free base's
// translation are differenced directly; a free base's rotation uses
// log(R_{t+1} R_{t-1}ᵀ) / (t_{t+1} − t_{t-1}), the ground-frame angular
// velocity Simbody's Free mobilizer expects. End frames use one-sided
// differences. Times need not be uniform.
void EstimateVelocities(const Model& model, const std::vector<double>& time_s, const std::vector<double>& q,
                        std::vector<double>& u, std::vector<double>& udot);

}  // namespace syn
