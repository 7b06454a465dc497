#include "stages/retarget/leg_reach.h"

#include <algorithm>
#include <cmath>

namespace syn {

std::vector<Leg> FindLegs(const Model& model, Workspace& workspace, int pelvis_link, const std::vector<int>& foot_tasks,
                          const std::vector<IkTask>& tasks) {
  std::vector<Leg> legs;
  if (pelvis_link < 0) return legs;
  const std::string& pelvis_name = model.linkNames()[static_cast<size_t>(pelvis_link)];
  const Eigen::Isometry3d pelvis_pose = workspace.findLinkPose(pelvis_link);
  for (size_t foot = 0; foot < foot_tasks.size(); ++foot) {
    const int foot_task = foot_tasks[foot];
    if (foot_task < 0) continue;
    const int foot_link = tasks[static_cast<size_t>(foot_task)].link;
    // Walk from the foot up to the pelvis; `hip` ends as the link just below it.
    std::string link = model.linkNames()[static_cast<size_t>(foot_link)], hip;
    for (size_t guard = 0; guard < model.joints().size() && !link.empty() && link != pelvis_name; ++guard) {
      const auto joint = std::find_if(model.joints().begin(), model.joints().end(),
                                      [&](const ModelJoint& candidate) { return candidate.child == link; });
      if (joint == model.joints().end()) break;
      hip = link;
      link = joint->parent;
    }
    if (link != pelvis_name || hip.empty()) continue;
    const int hip_link = model.findLinkIndex(hip);
    if (hip_link < 0) continue;
    const Eigen::Vector3d hip_world = workspace.findLinkPose(hip_link).translation();
    const Eigen::Vector3d ankle_world = workspace.findLinkPose(foot_link).translation();
    Leg leg;
    leg.foot = static_cast<int>(foot);
    leg.foot_task = foot_task;
    leg.hip_in_pelvis = pelvis_pose.inverse() * hip_world;
    leg.length = (hip_world - ankle_world).norm();
    if (leg.length > 0) legs.push_back(leg);
  }
  return legs;
}

LegReachReport LowerUpperBodyWithinReach(const std::vector<Leg>& legs, int pelvis_task, const FootContacts& contacts,
                                         const std::vector<double>& time_s, const LegReachOptions& options,
                                         std::vector<std::vector<IkTarget>>& frame_targets) {
  LegReachReport report;
  const int64_t frames = static_cast<int64_t>(frame_targets.size());
  if (legs.empty() || pelvis_task < 0 || frames == 0) return report;
  // The drop each frame needs on its own.
  std::vector<double> needed(static_cast<size_t>(frames), 0.0);
  for (int64_t t = 0; t < frames; ++t) {
    const std::vector<IkTarget>& frame = frame_targets[static_cast<size_t>(t)];
    if (frame.empty() || !frame[static_cast<size_t>(pelvis_task)].active) continue;
    const IkTarget& pelvis = frame[static_cast<size_t>(pelvis_task)];
    const Eigen::Matrix3d rotation =
        pelvis.has_orientation ? pelvis.orientation.normalized().toRotationMatrix() : Eigen::Matrix3d::Identity();
    bool unreachable = false;
    for (const Leg& leg : legs) {
      const IkTarget& foot = frame[static_cast<size_t>(leg.foot_task)];
      if (!foot.active || leg.foot >= contacts.feet || !contacts.at(t, leg.foot)) continue;
      const Eigen::Vector3d hip = pelvis.position + rotation * leg.hip_in_pelvis;
      const double reach = options.margin * leg.length;
      const double horizontal = (hip - foot.position).head<2>().norm();
      const double vertical = hip.z() - foot.position.z();
      double drop = 0;
      if (horizontal >= reach) {
        unreachable = true;
        drop = vertical;
      } else {
        drop = std::max(0.0, vertical - std::sqrt(reach * reach - horizontal * horizontal));
      }
      needed[static_cast<size_t>(t)] = std::max(needed[static_cast<size_t>(t)], std::min(drop, options.largest_drop * leg.length));
    }
    if (unreachable) ++report.unreachable_frames;
  }
  // Smoothed: a moving maximum keeps every frame's need, a moving mean of it removes the corners.
  auto window_of = [&](int64_t t, int64_t* begin, int64_t* end) {
    *begin = t, *end = t + 1;
    while (*begin > 0 && time_s[static_cast<size_t>(t)] - time_s[static_cast<size_t>(*begin - 1)] <= options.smoothing) --*begin;
    while (*end < frames && time_s[static_cast<size_t>(*end)] - time_s[static_cast<size_t>(t)] <= options.smoothing) ++*end;
  };
  std::vector<double> widened(needed.size()), drop(needed.size());
  for (int64_t t = 0; t < frames; ++t) {
    int64_t begin, end;
    window_of(t, &begin, &end);
    widened[static_cast<size_t>(t)] = *std::max_element(needed.begin() + begin, needed.begin() + end);
  }
  for (int64_t t = 0; t < frames; ++t) {
    int64_t begin, end;
    window_of(t, &begin, &end);
    double sum = 0;
    for (int64_t k = begin; k < end; ++k) sum += widened[static_cast<size_t>(k)];
    drop[static_cast<size_t>(t)] = sum / static_cast<double>(end - begin);
  }
  for (int64_t t = 0; t < frames; ++t) {
    const double d = drop[static_cast<size_t>(t)];
    if (d <= 0) continue;
    std::vector<IkTarget>& frame = frame_targets[static_cast<size_t>(t)];
    for (size_t i = 0; i < frame.size(); ++i) {
      const bool foot = std::any_of(legs.begin(), legs.end(), [&](const Leg& leg) { return leg.foot_task == static_cast<int>(i); });
      if (!foot && frame[i].active) frame[i].position.z() -= d;
    }
    ++report.lowered_frames;
    report.largest_drop = std::max(report.largest_drop, d);
  }
  return report;
}

}  // namespace syn
