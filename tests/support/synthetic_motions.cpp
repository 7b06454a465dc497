#include "tests/support/synthetic_motions.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <string>

namespace syn::testing {
namespace {

constexpr double kFrameRate = 120.0;

MotionData EmptyMotion(const Model& model) {
  MotionData motion;
  motion.coordinate_names = model.coordinateNames();
  motion.velocity_names = model.velocityNames();
  motion.model_name = model.name();
  motion.model_sha256 = model.sourceSha256();
  return motion;
}

void AppendFrame(MotionData& motion, double time, const Eigen::VectorXd& q, const Eigen::VectorXd& u,
                 const Eigen::VectorXd& udot) {
  motion.time_s.push_back(time);
  motion.q.insert(motion.q.end(), q.data(), q.data() + q.size());
  motion.u.insert(motion.u.end(), u.data(), u.data() + u.size());
  motion.udot.insert(motion.udot.end(), udot.data(), udot.data() + udot.size());
  motion.tau.insert(motion.tau.end(), static_cast<size_t>(u.size()), 0.0);
}

bool NameHas(const ModelJoint& joint, const char* part) { return joint.name.find(part) != std::string::npos; }

}  // namespace

double LowestSolePoint(const Model& model, const RobotMap& map, Workspace& workspace, const Eigen::VectorXd& q) {
  workspace.setQ(q);
  double lowest = std::numeric_limits<double>::infinity();
  for (const RobotFoot& foot : map.feet) {
    const Eigen::Isometry3d pose = workspace.findLinkPose(model.findLinkIndex(foot.link));
    for (const auto& p : foot.sole_points) lowest = std::min(lowest, (pose * Eigen::Vector3d(p[0], p[1], p[2])).z());
  }
  return lowest;
}

MotionData SwayingMotion(const Model& model, double seconds) {
  MotionData motion = EmptyMotion(model);
  const int frames = static_cast<int>(seconds * kFrameRate) + 1;
  for (int t = 0; t < frames; ++t) {
    const double time = t / kFrameRate;
    Eigen::VectorXd q = model.defaultQ(), u = Eigen::VectorXd::Zero(model.nu()), udot = u;
    q[6] = 0.75;  // pelvis height, m
    for (int i = 7; i < model.nq(); ++i) {
      const double w = 2.0 + 0.1 * i;  // rad/s
      q[i] = 0.2 * std::sin(w * time + i);
      u[i - 1] = 0.2 * w * std::cos(w * time + i);
      udot[i - 1] = -0.2 * w * w * std::sin(w * time + i);
    }
    AppendFrame(motion, time, q, u, udot);
  }
  return motion;
}

MotionData StandingMotion(const Model& model, const RobotMap& map, double seconds, double arm_swing) {
  Eigen::VectorXd stance = model.defaultQ();
  for (const ModelJoint& joint : model.joints()) {
    if (NameHas(joint, "knee")) stance[joint.q_index] = 0.3;
    if (NameHas(joint, "hip_pitch") || NameHas(joint, "ankle_pitch")) stance[joint.q_index] = -0.15;
  }
  stance[6] = 1.0;
  Workspace workspace(model);
  stance[6] -= LowestSolePoint(model, map, workspace, stance);
  MotionData motion = EmptyMotion(model);
  for (const RobotFoot& foot : map.feet) motion.contact_feet.push_back(foot.side);
  const double w = 2.0 * M_PI * 0.5;  // rad/s
  const int frames = static_cast<int>(seconds * kFrameRate) + 1;
  for (int t = 0; t < frames; ++t) {
    const double time = t / kFrameRate;
    Eigen::VectorXd q = stance, u = Eigen::VectorXd::Zero(model.nu()), udot = u;
    for (const ModelJoint& joint : model.joints()) {
      if (!NameHas(joint, "shoulder_pitch") && !NameHas(joint, "elbow")) continue;
      // G1's elbow zero is nearly straight, against a limit: a swinging elbow starts bent.
      const double offset = NameHas(joint, "elbow") && arm_swing > 0 ? 0.6 : 0.0;
      q[joint.q_index] += offset + arm_swing * (1.0 - std::cos(w * time));
      u[joint.u_index] = arm_swing * w * std::sin(w * time);
      udot[joint.u_index] = arm_swing * w * w * std::cos(w * time);
    }
    AppendFrame(motion, time, q, u, udot);
    motion.contact.insert(motion.contact.end(), map.feet.size(), 1);
  }
  return motion;
}

}  // namespace syn::testing
