#include "stages/retarget/foot_yaw_range.h"

#include <algorithm>
#include <cmath>

namespace syn {
namespace {

// A joint axis this close to vertical in the reference stance turns the foot about the vertical (G1's hip
// yaw axis is vertical; its pitch and roll axes are horizontal).
constexpr double kVerticalJointTolerance = 30.0 * M_PI / 180.0;

}  // namespace

YawRange FootYawRange(const Model& model, Workspace& workspace, const Eigen::VectorXd& q_reference, int pelvis_link,
                      int foot_link) {
  workspace.setQ(q_reference);
  const std::vector<std::string>& links = model.linkNames();
  const std::string& pelvis = links[static_cast<size_t>(pelvis_link)];
  YawRange range{0.0, 0.0};
  bool vertical = false;
  std::string link = links[static_cast<size_t>(foot_link)];
  while (link != pelvis) {
    const auto joint = std::find_if(model.joints().begin(), model.joints().end(),
                                    [&](const ModelJoint& candidate) { return candidate.child == link; });
    if (joint == model.joints().end() || joint->type == "free") return {};  // the root: not below the pelvis
    if (joint->type == "revolute" && joint->q_index >= 0) {
      const Eigen::Isometry3d frame = workspace.findLinkPose(model.findLinkIndex(joint->parent)) * joint->origin;
      const double up = (frame.linear() * joint->axis).normalized().z();
      if (std::abs(up) >= std::cos(kVerticalJointTolerance)) {
        const double lower = model.qLower()[joint->q_index], upper = model.qUpper()[joint->q_index];
        range.lower += up > 0 ? lower : -upper;
        range.upper += up > 0 ? upper : -lower;
        vertical = true;
      }
    }
    link = joint->parent;
  }
  if (!vertical || !std::isfinite(range.lower) || !std::isfinite(range.upper)) return {};
  range.lower = std::max(range.lower, -M_PI), range.upper = std::min(range.upper, M_PI);
  return range;
}

bool HoldFootYaw(const Eigen::Quaterniond& pelvis, const Eigen::Quaterniond& reference, const YawRange& range,
                 Eigen::Quaterniond& foot) {
  // foot = pelvis · turn · swing · reference: the turn about the pelvis's z, then what tilts it.
  const Eigen::Quaterniond deviation = pelvis.conjugate() * foot * reference.conjugate();
  Eigen::Quaterniond turn(deviation.w(), 0.0, 0.0, deviation.z());
  if (turn.norm() < 1e-12) return false;  // a half-turn about a horizontal axis: no turn to measure
  turn.normalize();
  const double angle = std::remainder(2.0 * std::atan2(turn.z(), turn.w()), 2.0 * M_PI);
  const double held = std::clamp(angle, range.lower, range.upper);
  if (held == angle) return false;
  const Eigen::Quaterniond swing = turn.conjugate() * deviation;
  foot = (pelvis * Eigen::Quaterniond(Eigen::AngleAxisd(held, Eigen::Vector3d::UnitZ())) * swing * reference).normalized();
  return true;
}

}  // namespace syn
