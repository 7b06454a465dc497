// syn-synergies: PCA synergies of every segment of a motion (the file format
// is common/synergies_file.h).
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/motion_file.h"
#include "common/synergies_file.h"
#include "stages/synergies/segment_pca.h"

namespace syn {

// Which generalized velocities the PCA sees.
enum class VelocitySet {
  kAll,     // every velocity; a free base's in the pelvis heading frame
  kJoints,  // the joints only (a free base's six velocities left out)
};
[[nodiscard]] const char* VelocitySetName(VelocitySet set);

struct SynergyOptions {
  int components = 3;                        // paper: three synergies reach ≥ 90 % in every genre
  VelocitySet velocities = VelocitySet::kAll;
  SynergyLabels labels;                      // from the manifest

  bool IsValid(std::string* error) const;
  nlohmann::json ToJson() const;
};

// The velocity samples of frames [start, end) as PCA sees them.
[[nodiscard]] Eigen::MatrixXd SegmentVelocities(const MotionData& motion, bool free_base, int64_t start, int64_t end,
                                                VelocitySet which);

[[nodiscard]] TrialSynergies ComputeTrialSynergies(const MotionData& motion, const std::vector<int64_t>& boundaries,
                                                   const SynergyOptions& options);

}  // namespace syn
