// `*.synergies.h5` (schema synsculpt.synergies): every segment's postural
// synergies of one trial. Written by syn-synergies; read by syn-library,
// syn-evaluate and syn-summary. Libraries (common/library_file.h) store
// segments in the same group layout, without the velocity samples.
//
// Root: velocity_names[nv]; attributes subject, trial, style, motion_class,
// segment_count. Per segment, group "segments/NNN": q0[nq], times[Ts] (s from
// the segment's first frame), mean_u[nv], components[k,nv],
// singular_values[k], explained_variance_ratio[k], scores[Ts,k] and (trial
// files only) velocities[Ts,nv]; attributes duration, start_frame, end_frame,
// components_for_90_percent.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/intermediate_file.h"
#include "common/segment_synergies.h"

namespace syn {

inline constexpr const char* kSynergiesSchema = "synsculpt.synergies";
inline constexpr int64_t kSynergiesSchemaVersion = 1;

// Where a trial's synergies come from (the manifest's labels); they travel into libraries and summaries.
struct SynergyLabels {
  std::string subject, trial, style, motion_class;

  nlohmann::json ToJson() const;
};

struct TrialSynergies {
  std::vector<std::string> velocity_names;  // [nv]
  struct Segment {
    int64_t start_frame = 0, end_frame = 0;  // [start, end)
    double duration = 0.0;
    std::vector<double> q0;
    std::vector<double> times;   // [Ts] s from the segment's first frame (the scores' sample instants)
    Eigen::MatrixXd velocities;  // [Ts, nv] the samples the PCA saw
    SegmentSynergies synergies;
  };
  std::vector<Segment> segments;
};

void WriteTrialSynergies(IntermediateWriter& writer, const TrialSynergies& synergies, const SynergyLabels& labels);
[[nodiscard]] TrialSynergies ReadTrialSynergies(const std::string& path, SynergyLabels* labels);

// One segment's group ("segments/007"); `with_samples` adds the velocity samples the PCA saw.
[[nodiscard]] std::string SegmentGroupName(size_t segment);
void WriteSynergySegment(IntermediateWriter& writer, const std::string& group, const TrialSynergies::Segment& segment,
                         bool with_samples);
[[nodiscard]] TrialSynergies::Segment ReadSynergySegment(const IntermediateReader& reader, const std::string& group);

// The label attributes of `group` ("" = root), as written by WriteTrialSynergies and WriteLibrary.
void WriteSynergyLabels(IntermediateWriter& writer, const std::string& group, const SynergyLabels& labels);
[[nodiscard]] SynergyLabels ReadSynergyLabels(const IntermediateReader& reader, const std::string& group);

}  // namespace syn
