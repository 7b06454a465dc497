// The archive's summary tables: one CSV row per trial and one per segment,
// from the trials' synergies files (which carry the manifest's labels).
#pragma once

#include <string>
#include <vector>

namespace syn {

// Writes the table ("trials" or "segments") to `output` (temporary name, then
// renamed). Rows follow the order of `synergies_files`; numbers use "%.6g",
// so the same inputs give the same bytes. With `metrics_files` (syn-evaluate
// JSON, one per synergies file), each row also gets the trial's or segment's
// mean ΔP, ΔKE, power, foot sliding and the rank-k reconstruction's change.
void WriteSummaryTable(const std::vector<std::string>& synergies_files, const std::vector<std::string>& metrics_files,
                       const std::string& table, const std::string& output);

}  // namespace syn
