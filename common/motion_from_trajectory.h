// A complete motion file's content from a configuration and velocity
// trajectory that a stage computed (compose, project): accelerations by
// central differences of the velocity samples (one-sided at the ends; times
// need not be uniform) and tau by Simbody inverse dynamics (gravity, no
// contact, as syn-retarget).
#pragma once

#include <vector>

#include <Eigen/Core>

#include "common/model.h"
#include "common/motion_file.h"

namespace syn {

// q: [T, nq], u: [T, nu] (ground-frame base velocities).
[[nodiscard]] MotionData MotionFromTrajectory(const Model& model, const std::vector<double>& times, const Eigen::MatrixXd& q,
                                              const Eigen::MatrixXd& u);

}  // namespace syn
