// Synthetic G1-style motions with a known shape, for syn-simulate's tests and benchmark: no capture
// needed, every frame's q, u and udot consistent (u and udot are the exact derivatives of q).
#pragma once

#include "common/model.h"
#include "common/motion_file.h"
#include "common/robot_map.h"

namespace syn::testing {

// The height of the lowest of the map's sole points at q (m; negative below the floor).
double LowestSolePoint(const Model& model, const RobotMap& map, Workspace& workspace, const Eigen::VectorXd& q);

// Every joint a sinusoid of 0.2 rad (2 to 5 rad/s), the pelvis held 0.75 m up: a motion the paper's
// driven base tracks anywhere, sampled at 120 Hz.
MotionData SwayingMotion(const Model& model, double seconds);

// The robot standing: the zero pose with knees (0.3 rad) and hips and ankles (-0.15) a little bent, the
// pelvis at the height that puts the map's lowest sole point on z = 0 (FK here), both feet marked in
// contact. With `arm_swing` > 0 the elbows are bent 0.6 rad more and the shoulder pitch and elbow joints
// swing up to `arm_swing` rad from that pose at 0.5 Hz; 0 holds the pose still.
MotionData StandingMotion(const Model& model, const RobotMap& map, double seconds, double arm_swing = 0.0);

}  // namespace syn::testing
