// `--contact ground`: the simulation starts on the balance plan's first state.
//
// The balance plan (balanced_reference.h) is free at its start: a take that begins mid-stride begins with
// the centre of mass already leaning and moving towards the next stance foot, which the retargeted motion,
// copying the person, does not do. Started from the motion's own state, the robot began 4-5 cm and a few
// cm/s off its plan, which on a 5 cm sole it never caught up. So the base is shifted horizontally by the
// plan's first shift and given its rate, and each 6-joint leg is re-solved (damped least squares, steps of
// at most 0.1 rad: a straight knee makes the leg singular) so its foot keeps the pose and velocity it had.
// A leg with another number of joints is left as it is (its foot moves with the base). The legs stay inside
// the URDF's limits: where they cannot keep the feet for the whole shift, the base takes the largest of
// its halves, quarters, ... that they can, and none if no share is reachable.
#pragma once

#include <Eigen/Core>

#include "common/model.h"
#include "common/robot_map.h"
#include "stages/simulate/balanced_reference.h"

namespace syn {

// q, u: a free-base robot's state (the base's position at q[4..6], its linear velocity at u[3..5]),
// changed in place. `workspace` belongs to `model`.
void StartOnThePlan(const Model& model, const RobotMap& map, const BalanceShift& plan, Workspace& workspace,
                    Eigen::VectorXd& q, Eigen::VectorXd& u);

}  // namespace syn
