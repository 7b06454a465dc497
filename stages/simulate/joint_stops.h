// `--contact ground`: the joints' mechanical stops, part of the simulated robot.
//
// The controller keeps only the branch joints (knees, straight-limb elbows) inside their URDF limits
// (operational_space_controller.h); every other joint of the simulated robot could turn without end. On
// the ground that let the robots of the CMU walks that "stayed up" lean on ankle rolls 8-105° past G1's
// ±15° (02_01's left ankle turned round 2.5 times in the air), in 14-40 % of their frames: a balance no
// G1 has. So each actuated joint with finite limits gets a stop, as a real joint has: past a limit, a stiff
// spring and damper push it back, τ = min(0, −k (q − upper) − b q̇) (and mirrored at the lower limit),
// never pulling. The stops' stiffness and damping join the contact's in the simulation's linearly implicit
// step, so a stop as hard as a light wrist's stays stable at 1 kHz, and a joint that would cross its limit
// within the step at its present speed is engaged before it does.
#pragma once

#include <vector>

#include <Eigen/Core>

#include "common/model.h"

namespace syn {

struct JointStopOptions {
  // N·m/rad: a joint pressed by 50 N·m (G1's ankle roll) stops 0.5 mrad past its limit. At 2·10⁴ the CMU
  // walks' ankle rolls went up to 3.1° past theirs on landing and the robots that stayed up sagged to 71 %
  // of their pelvis height; at 10⁵ (engaged a step ahead, add()), 0.4° and 97 %.
  double stiffness = 100000.0;
  double damping = 20.0;  // N·m·s/rad
};

class JointStops {
 public:
  JointStops(const Model& model, const JointStopOptions& options);

  // Adds the stops' generalized forces at (q, u) to `forces` (nu), and their stiffness and damping
  // (−∂τ/∂q, −∂τ/∂q̇ on the diagonal) to `stiffness` and `damping` (nu × nu), for a linearly implicit
  // step of `step` seconds (0: engage only joints already past a limit). Returns how many are engaged.
  int add(const Eigen::VectorXd& q, const Eigen::VectorXd& u, double step, Eigen::VectorXd& forces, Eigen::MatrixXd& stiffness,
          Eigen::MatrixXd& damping) const;
  // How far (rad) the joint farthest past its limit is at q (0 if none is).
  double worstExcess(const Eigen::VectorXd& q) const;

 private:
  struct Stop {
    int q_index, u_index;
    double lower, upper;
  };
  JointStopOptions options_;
  std::vector<Stop> stops_;
};

}  // namespace syn
