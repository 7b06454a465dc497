#include "stages/synergies/synergies.h"

#include <cmath>

#include <Eigen/Geometry>

#include "common/error.h"

namespace syn {

bool SynergyOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& message) {
    if (error) *error = message;
    return false;
  };
  if (components < 1) return fail("--components must be at least 1");
  return true;
}

const char* VelocitySetName(VelocitySet set) { return set == VelocitySet::kJoints ? "joints" : "all"; }

nlohmann::json SynergyOptions::ToJson() const {
  nlohmann::json json = labels.ToJson();
  json["components"] = components;
  json["velocities"] = VelocitySetName(velocities);
  return json;
}

Eigen::MatrixXd SegmentVelocities(const MotionData& motion, bool free_base, int64_t start, int64_t end,
                                  VelocitySet which) {
  const int64_t nq = motion.nq(), nu = motion.nu();
  const int64_t skip = (which == VelocitySet::kJoints && free_base) ? 6 : 0;
  Eigen::MatrixXd samples(end - start, nu - skip);
  for (int64_t t = start; t < end; ++t) {
    Eigen::Map<const Eigen::VectorXd> u(&motion.u[static_cast<size_t>(t * nu)], nu);
    Eigen::VectorXd row = u.tail(nu - skip);
    if (free_base && skip == 0) {
      // Base velocities in the pelvis heading frame: a synergy must not depend on which way the subject faced.
      const double* q = &motion.q[static_cast<size_t>(t * nq)];
      const Eigen::Matrix3d rotation = Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized().toRotationMatrix();
      const double yaw = std::atan2(rotation(1, 0), rotation(0, 0));
      const Eigen::Matrix3d unturn = Eigen::AngleAxisd(-yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
      row.head<3>() = unturn * row.head<3>();
      row.segment<3>(3) = unturn * row.segment<3>(3);
    }
    samples.row(t - start) = row.transpose();
  }
  return samples;
}

TrialSynergies ComputeTrialSynergies(const MotionData& motion, const std::vector<int64_t>& boundaries,
                                     const SynergyOptions& options) {
  const bool free_base = motion.nq() == motion.nu() + 1;
  TrialSynergies result;
  const int64_t skip = (options.velocities == VelocitySet::kJoints && free_base) ? 6 : 0;
  result.velocity_names.assign(motion.velocity_names.begin() + skip, motion.velocity_names.end());
  for (size_t s = 0; s + 1 < boundaries.size(); ++s) {
    const int64_t start = boundaries[s], end = std::min(boundaries[s + 1], motion.frames());
    if (end - start < 2) continue;
    TrialSynergies::Segment segment;
    segment.start_frame = start;
    segment.end_frame = end;
    segment.duration = motion.time_s[static_cast<size_t>(end - 1)] - motion.time_s[static_cast<size_t>(start)];
    segment.q0.assign(motion.q.begin() + start * motion.nq(), motion.q.begin() + (start + 1) * motion.nq());
    for (int64_t t = start; t < end; ++t) {
      segment.times.push_back(motion.time_s[static_cast<size_t>(t)] - motion.time_s[static_cast<size_t>(start)]);
    }
    segment.velocities = SegmentVelocities(motion, free_base, start, end, options.velocities);
    segment.synergies = ComputeSegmentSynergies(segment.velocities, options.components);
    result.segments.push_back(std::move(segment));
  }
  return result;
}

}  // namespace syn
