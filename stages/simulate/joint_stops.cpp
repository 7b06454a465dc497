#include "stages/simulate/joint_stops.h"

#include <algorithm>
#include <cmath>

namespace syn {

JointStops::JointStops(const Model& model, const JointStopOptions& options) : options_(options) {
  for (const ModelJoint& joint : model.joints()) {
    if (joint.u_index < 0 || joint.q_index < 0 || joint.type == "free") continue;
    if (!model.actuatedVelocities()[static_cast<size_t>(joint.u_index)]) continue;  // a virtual base's joints
    const double lower = model.qLower()[joint.q_index], upper = model.qUpper()[joint.q_index];
    if (std::isfinite(lower) && std::isfinite(upper) && upper > lower) stops_.push_back({joint.q_index, joint.u_index, lower, upper});
  }
}

int JointStops::add(const Eigen::VectorXd& q, const Eigen::VectorXd& u, Eigen::VectorXd& forces, Eigen::MatrixXd& stiffness,
                    Eigen::MatrixXd& damping) const {
  int pushing = 0;
  for (const Stop& stop : stops_) {
    const double position = q[stop.q_index], velocity = u[stop.u_index];
    double torque = 0.0;
    if (position > stop.upper) {
      torque = std::min(0.0, -options_.stiffness * (position - stop.upper) - options_.damping * velocity);
    } else if (position < stop.lower) {
      torque = std::max(0.0, -options_.stiffness * (position - stop.lower) - options_.damping * velocity);
    }
    if (torque == 0.0) continue;
    forces[stop.u_index] += torque;
    stiffness(stop.u_index, stop.u_index) += options_.stiffness;
    damping(stop.u_index, stop.u_index) += options_.damping;
    ++pushing;
  }
  return pushing;
}

double JointStops::worstExcess(const Eigen::VectorXd& q) const {
  double worst = 0.0;
  for (const Stop& stop : stops_) worst = std::max({worst, q[stop.q_index] - stop.upper, stop.lower - q[stop.q_index]});
  return worst;
}

}  // namespace syn
