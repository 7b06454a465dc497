// Style-conditioned synergy libraries (paper, "Stylistic Variability across
// Dance Synergies"): per style, one shared basis from all of its segments'
// velocity samples (each segment centred on its own mean), the variance that
// basis retains on each trial, and per motion class the spread of the
// per-segment PC1–PC3 variance ratios (the paper's Fig. 4 and Fig. 5 data).
// The file format is common/library_file.h.
#pragma once

#include <string>
#include <vector>

#include "common/library_file.h"

namespace syn {

// Throws DataError (naming `sources[i]`) when trials disagree on velocity names.
[[nodiscard]] SynergyLibrary BuildLibrary(const std::vector<LabelledTrial>& trials, const std::vector<std::string>& sources,
                                          int components);

}  // namespace syn
