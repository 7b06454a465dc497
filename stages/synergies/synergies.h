// syn-synergies: PCA synergies of every segment of a motion.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/intermediate_file.h"
#include "common/motion_file.h"
#include "stages/synergies/segment_pca.h"

namespace syn {

inline constexpr const char* kSynergiesSchema = "synsculpt.synergies";
inline constexpr int64_t kSynergiesSchemaVersion = 1;

struct SynergyOptions {
  int components = 3;                 // paper: three synergies reach ≥ 90 % in every genre
  std::string velocities = "all";     // "all" (free-base velocities in the pelvis heading frame) or "joints"
  // Labels for the library (from the manifest).
  std::string subject, trial, style, motion_class;

  bool IsValid(std::string* error) const;
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

// The velocity samples of frames [start, end) as PCA sees them (see SynergyOptions::velocities).
[[nodiscard]] Eigen::MatrixXd SegmentVelocities(const MotionData& motion, bool free_base, int64_t start, int64_t end,
                                                const std::string& which);

[[nodiscard]] TrialSynergies ComputeTrialSynergies(const MotionData& motion, const std::vector<int64_t>& boundaries,
                                                   const SynergyOptions& options);

void WriteTrialSynergies(IntermediateWriter& writer, const TrialSynergies& synergies, const SynergyOptions& options);

// One segment's group ("segments/007"), as synergies files and libraries store it; `with_samples` adds
// the velocity samples the PCA saw (libraries leave them out).
[[nodiscard]] std::string SegmentGroupName(size_t segment);
void WriteSynergySegment(IntermediateWriter& writer, const std::string& group, const TrialSynergies::Segment& segment,
                         bool with_samples);
[[nodiscard]] TrialSynergies::Segment ReadSynergySegment(const IntermediateReader& reader, const std::string& group);
[[nodiscard]] TrialSynergies ReadTrialSynergies(const std::string& path, SynergyOptions* labels);

}  // namespace syn
