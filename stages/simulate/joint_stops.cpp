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

int JointStops::add(const Eigen::VectorXd& q, const Eigen::VectorXd& u, double step, Eigen::VectorXd& forces,
                    Eigen::MatrixXd& stiffness, Eigen::MatrixXd& damping) const {
  int engaged_stops = 0;
  for (const Stop& stop : stops_) {
    const double position = q[stop.q_index], velocity = u[stop.u_index], ahead = position + step * velocity;
    // Engaged past a limit while it pushes, or a step ahead of it while the joint moves into it: the stop
    // then joins the implicit step before the joint crosses, which gives its force at the step's end,
    // −k (q + h q̇' − limit) − b q̇'. Engaged only once past, a stop took a joint a whole step's travel
    // (a landing ankle roll at 30 rad/s: 1.7°) beyond its limit before pushing.
    double torque = 0.0;
    bool engaged = false;
    if (position > stop.upper || ahead > stop.upper) {
      torque = std::min(0.0, -options_.stiffness * (position - stop.upper) - options_.damping * velocity);
      engaged = torque < 0.0 || velocity > 0.0;
    } else if (position < stop.lower || ahead < stop.lower) {
      torque = std::max(0.0, -options_.stiffness * (position - stop.lower) - options_.damping * velocity);
      engaged = torque > 0.0 || velocity < 0.0;
    }
    if (!engaged) continue;
    forces[stop.u_index] += torque;
    stiffness(stop.u_index, stop.u_index) += options_.stiffness;
    damping(stop.u_index, stop.u_index) += options_.damping;
    ++engaged_stops;
  }
  return engaged_stops;
}

double JointStops::worstExcess(const Eigen::VectorXd& q) const {
  double worst = 0.0;
  for (const Stop& stop : stops_) worst = std::max({worst, q[stop.q_index] - stop.upper, stop.lower - q[stop.q_index]});
  return worst;
}

}  // namespace syn
