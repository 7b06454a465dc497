// What each stage accepts, learned from the stage itself: syn-plan runs
// `syn-<stage> --print-parameters` (common/cli.h) and takes the names of the
// JSON it prints. One source of truth for parameter names and defaults — the
// stage's options struct — without linking any stage's code into syn-plan.
#pragma once

#include <string>
#include <vector>

#include "stages/plan/manifest.h"

namespace syn {

// The per-trial stages' parameter names, from the syn-* tools in `bin_dir`. Labels (synergies' subject,
// trial, style, motion class) come from the trial, and library's style from the job, so they are left out.
// Throws DataError naming the tool when one is missing or prints no JSON object.
[[nodiscard]] std::vector<StageParameterNames> QueryStageParameters(const std::string& bin_dir);

// Every per-trial stage's values, checked by the stage itself: `syn-<stage> --print-parameters FLAGS`
// with the flags the manifest gives it (once per distinct set). A refusal is a DataError at the first
// trial's manifest line, with the stage's own message, before make runs anything (`contact = "floor"`
// used to plan fine and fail at make time, trial by trial).
void CheckParameterValues(const Manifest& manifest, const std::string& bin_dir);

// The folder holding the running executable (where the other syn-* tools are built).
[[nodiscard]] std::string OwnExecutableFolder();

}  // namespace syn
