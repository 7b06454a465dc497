// Style-conditioned synergy libraries (paper, "Stylistic Variability across
// Dance Synergies"): per style, one shared basis from all of its segments'
// velocity samples (each segment centred on its own mean), the variance that
// basis retains on each trial, and per motion class the spread of the
// per-segment PC1–PC3 variance ratios (the paper's Fig. 4 and Fig. 5 data).
#pragma once

#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "common/intermediate_file.h"
#include "stages/synergies/synergies.h"

namespace syn {

struct StyleBasis {
  Eigen::MatrixXd components;             // [k, nv], orthonormal rows: Sᵀ
  Eigen::VectorXd singular_values;        // [k]
  Eigen::VectorXd explained_variance_ratio;  // [k]
  std::vector<std::string> trials;
  std::vector<double> retained_variance;  // per trial: ‖Xc S Sᵀ‖² / ‖Xc‖² over its segments
  int64_t segments = 0;
};

struct ClassSpread {
  Eigen::VectorXd mean_ratio, std_ratio;  // [3]: PC1..PC3 explained-variance ratio over segments
  int64_t segments = 0;
};

struct SynergyLibrary {
  std::vector<std::string> velocity_names;
  std::map<std::string, StyleBasis> styles;
  std::map<std::string, ClassSpread> classes;
};

struct LabelledTrial {
  SynergyOptions labels;
  TrialSynergies synergies;
};

// Throws DataError (naming `sources[i]`) when trials disagree on velocity names.
[[nodiscard]] SynergyLibrary BuildLibrary(const std::vector<LabelledTrial>& trials, const std::vector<std::string>& sources,
                                          int components);

void WriteLibrary(IntermediateWriter& writer, const SynergyLibrary& library);

}  // namespace syn
