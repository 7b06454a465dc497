#include "common/synergies_file.h"

#include <cstdio>

#include "common/error.h"
#include "common/row_major.h"

namespace syn {

nlohmann::json SynergyLabels::ToJson() const {
  return {{"subject", subject}, {"trial", trial}, {"style", style}, {"motion_class", motion_class}};
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

void WriteSynergyLabels(IntermediateWriter& writer, const std::string& group, const SynergyLabels& labels) {
  for (const char* key : {"subject", "trial", "style", "motion_class"}) {
    writer.writeAttribute(group, key, labels.ToJson()[key].get<std::string>());
  }
}

SynergyLabels ReadSynergyLabels(const IntermediateReader& reader, const std::string& group) {
  SynergyLabels labels;
  labels.subject = reader.readStringAttribute(group, "subject");
  labels.trial = reader.readStringAttribute(group, "trial");
  labels.style = reader.readStringAttribute(group, "style");
  labels.motion_class = reader.readStringAttribute(group, "motion_class");
  return labels;
}

void WriteTrialSynergies(IntermediateWriter& writer, const TrialSynergies& synergies, const SynergyLabels& labels) {
  writer.writeStrings("velocity_names", synergies.velocity_names);
  WriteSynergyLabels(writer, "", labels);
  writer.writeAttribute("", "segment_count", static_cast<int64_t>(synergies.segments.size()));
  for (size_t s = 0; s < synergies.segments.size(); ++s) {
    WriteSynergySegment(writer, SegmentGroupName(s), synergies.segments[s], true);
  }
}

TrialSynergies ReadTrialSynergies(const std::string& path, SynergyLabels* labels) {
  IntermediateReader reader(path, kSynergiesSchema, kSynergiesSchemaVersion);
  TrialSynergies result;
  result.velocity_names = reader.readStrings("velocity_names");
  if (labels) *labels = ReadSynergyLabels(reader, "");
  const int64_t count = reader.readIntAttribute("", "segment_count");
  for (int64_t s = 0; s < count; ++s) result.segments.push_back(ReadSynergySegment(reader, SegmentGroupName(static_cast<size_t>(s))));
  return result;
}

}  // namespace syn
