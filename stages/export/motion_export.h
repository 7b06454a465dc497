// syn-export: a motion file as text other tools read.
//
//   csv        time and every coordinate, named header (q as stored: a free base as quaternion w,x,y,z
//              and position; joints in rad or m)
//   mot        OpenSim motion (version=1, nRows, nColumns, inDegrees=yes, endheader; tab-separated):
//              revolute joints in degrees, a free base as body-fixed X-Y-Z angles (degrees) and position;
//              axes are synsculpt's (Z up), not OpenSim's Y-up ground
//   robot-csv  the joint CSV of current humanoid tooling (e.g. ../shared/datasets/robot_motion/ for G1):
//              no header, one row per frame: root position x,y,z, root quaternion w,x,y,z, then the joint
//              positions in URDF file order; uniform rate (--rate, default the motion's own)
#pragma once

#include <optional>
#include <string>

#include "common/model.h"
#include "common/motion_file.h"

namespace syn {

// A uniformly resampled copy of the motion's poses (cubic, quaternion signs made continuous and
// renormalised); velocities are dropped. Throws DataError if the motion has fewer than 2 frames.
[[nodiscard]] MotionData ResampleUniformly(const MotionData& motion, double rate);

[[nodiscard]] std::string MotionToCsv(const MotionData& motion);
[[nodiscard]] std::string MotionToMot(const MotionData& motion, const Model& model, const std::string& name);
[[nodiscard]] std::string MotionToRobotCsv(const MotionData& motion, const Model& model);

// Reads a robot CSV back into poses on `model` at `rate` Hz. Throws DataError (file:line) for a row
// of the wrong width or a value that is not a number.
[[nodiscard]] MotionData ReadRobotCsv(const std::string& path, const Model& model, double rate);

}  // namespace syn
