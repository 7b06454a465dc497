// The robot as tools/report/player.js draws it, from the URDF: the same JSON tools/report/urdf_fk.py
// Robot.description() writes for the report (links in breadth-first tree order, each with its parent
// index, joint origin as xyz and quaternion w,x,y,z, axis, type and coordinate index in q; the free base's
// q indexes; the robot map's feet), computed here so that the studio needs no Python at run time.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/model.h"
#include "common/robot_map.h"

namespace syn {

[[nodiscard]] nlohmann::json PlayerRobotDescription(const std::string& urdf_path, const Model& model,
                                                    const RobotMap& map);

}  // namespace syn
