#include "stages/synergies/synergies.h"

#include <cmath>
#include <cstdio>

#include <Eigen/Geometry>

#include "common/error.h"
#include "common/row_major.h"

namespace syn {

bool SynergyOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& message) {
    if (error) *error = message;
    return false;
  };
  if (components < 1) return fail("--components must be at least 1");
  if (velocities != "all" && velocities != "joints") return fail("--velocities must be all or joints");
  return true;
}

nlohmann::json SynergyOptions::ToJson() const {
  return {{"components", components}, {"velocities", velocities}, {"subject", subject},
          {"trial", trial}, {"style", style}, {"motion_class", motion_class}};
}

Eigen::MatrixXd SegmentVelocities(const MotionData& motion, bool free_base, int64_t start, int64_t end,
                                  const std::string& which) {
  const int64_t nq = motion.nq(), nu = motion.nu();
  const int64_t skip = (which == "joints" && free_base) ? 6 : 0;
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
  const int64_t skip = (options.velocities == "joints" && free_base) ? 6 : 0;
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

std::string SegmentGroupName(size_t segment) {
  char name[32];
  std::snprintf(name, sizeof name, "segments/%03zu", segment);
  return name;
}

void WriteSynergySegment(IntermediateWriter& writer, const std::string& group, const TrialSynergies::Segment& segment,
                         bool with_samples) {
  const SegmentSynergies& pca = segment.synergies;
  const int64_t k = pca.components.rows(), nv = pca.components.cols(), ts = pca.scores.rows();
  writer.writeDoubles(group + "/q0", segment.q0);
  writer.writeDoubles(group + "/times", segment.times);
  writer.writeDoubles(group + "/mean_u", std::vector<double>(pca.mean.data(), pca.mean.data() + nv));
  writer.writeDoubles(group + "/components", {k, nv}, RowMajorValues(pca.components).data());
  writer.writeDoubles(group + "/singular_values", std::vector<double>(pca.singular_values.data(), pca.singular_values.data() + k));
  writer.writeDoubles(group + "/explained_variance_ratio",
                      std::vector<double>(pca.explained_variance_ratio.data(), pca.explained_variance_ratio.data() + k));
  writer.writeDoubles(group + "/scores", {ts, k}, RowMajorValues(pca.scores).data());
  if (with_samples) writer.writeDoubles(group + "/velocities", {ts, nv}, RowMajorValues(segment.velocities).data());
  writer.writeAttribute(group, "duration", segment.duration);
  writer.writeAttribute(group, "start_frame", segment.start_frame);
  writer.writeAttribute(group, "end_frame", segment.end_frame);
  writer.writeAttribute(group, "components_for_90_percent", static_cast<int64_t>(pca.components_for_90_percent));
}

TrialSynergies::Segment ReadSynergySegment(const IntermediateReader& reader, const std::string& group) {
  auto vector = [](const std::vector<double>& values) {
    return Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(values.data(), static_cast<Eigen::Index>(values.size())));
  };
  TrialSynergies::Segment segment;
  segment.q0 = reader.readDoubles(group + "/q0").values;
  segment.synergies.mean = vector(reader.readDoubles(group + "/mean_u").values);
  segment.synergies.components = MatrixFromRowMajor(reader.readDoubles(group + "/components"));
  segment.synergies.singular_values = vector(reader.readDoubles(group + "/singular_values").values);
  segment.synergies.explained_variance_ratio = vector(reader.readDoubles(group + "/explained_variance_ratio").values);
  segment.synergies.scores = MatrixFromRowMajor(reader.readDoubles(group + "/scores"));
  if (reader.has(group + "/velocities")) segment.velocities = MatrixFromRowMajor(reader.readDoubles(group + "/velocities"));
  segment.duration = reader.readDoubleAttribute(group, "duration");
  segment.start_frame = reader.readIntAttribute(group, "start_frame");
  segment.end_frame = reader.readIntAttribute(group, "end_frame");
  segment.synergies.components_for_90_percent = static_cast<int>(reader.readIntAttribute(group, "components_for_90_percent"));
  if (reader.has(group + "/times")) {
    segment.times = reader.readDoubles(group + "/times").values;
  } else {  // files from before 0.1.0 stored no times: their frames were uniform
    const Eigen::Index samples = segment.synergies.scores.rows();
    const Eigen::VectorXd uniform = Eigen::VectorXd::LinSpaced(samples, 0.0, segment.duration);
    segment.times.assign(uniform.data(), uniform.data() + samples);
  }
  if (static_cast<int64_t>(segment.times.size()) != segment.synergies.scores.rows() ||
      segment.synergies.components.cols() != segment.synergies.mean.size() ||
      segment.synergies.scores.cols() != segment.synergies.components.rows() ||
      segment.synergies.singular_values.size() != segment.synergies.components.rows()) {
    throw DataError(Location::InFile(reader.path()), group + ": times, scores, components and singular values disagree in size");
  }
  return segment;
}

void WriteTrialSynergies(IntermediateWriter& writer, const TrialSynergies& synergies, const SynergyOptions& options) {
  writer.writeStrings("velocity_names", synergies.velocity_names);
  for (const char* key : {"subject", "trial", "style", "motion_class"}) {
    writer.writeAttribute("", key, options.ToJson()[key].get<std::string>());
  }
  writer.writeAttribute("", "segment_count", static_cast<int64_t>(synergies.segments.size()));
  for (size_t s = 0; s < synergies.segments.size(); ++s) {
    WriteSynergySegment(writer, SegmentGroupName(s), synergies.segments[s], true);
  }
}

TrialSynergies ReadTrialSynergies(const std::string& path, SynergyOptions* labels) {
  IntermediateReader reader(path, kSynergiesSchema, kSynergiesSchemaVersion);
  TrialSynergies result;
  result.velocity_names = reader.readStrings("velocity_names");
  if (labels) {
    labels->subject = reader.readStringAttribute("", "subject");
    labels->trial = reader.readStringAttribute("", "trial");
    labels->style = reader.readStringAttribute("", "style");
    labels->motion_class = reader.readStringAttribute("", "motion_class");
  }
  const int64_t count = reader.readIntAttribute("", "segment_count");
  for (int64_t s = 0; s < count; ++s) result.segments.push_back(ReadSynergySegment(reader, SegmentGroupName(static_cast<size_t>(s))));
  return result;
}

}  // namespace syn
