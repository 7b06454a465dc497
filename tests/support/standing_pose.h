// The robot map's reference stance, computed for tests: the zero pose (identity base orientation, every
// joint 0) with the base at x = y = 0 and raised until the lowest sole point of the map's feet touches z = 0.
#pragma once

#include <Eigen/Core>

#include "common/model.h"
#include "common/robot_map.h"

namespace syn::testing {

Eigen::VectorXd StandingZeroPose(const Model& model, const RobotMap& map);

}  // namespace syn::testing
