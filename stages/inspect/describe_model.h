// The JSON description of a robot model that `syn-inspect ROBOT.urdf` prints.
#pragma once

#include <string>

#include <nlohmann/json.hpp>

namespace syn {

// Loads the URDF as every stage would (same floating-base rule) and lists
// nq, nu, total mass, coordinate and velocity names, links and joints.
[[nodiscard]] nlohmann::json DescribeModel(const std::string& urdf_path, const std::string& floating_base);

}  // namespace syn
