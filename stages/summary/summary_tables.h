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

// Human-vs-robot mechanical power per trial: each trial retargeted onto a robot and onto a human model
// (syn-human's de Leva model, or any URDF), both evaluated alike by syn-evaluate. Columns: trial, subject,
// motion_class, robot (`robot_name`), human and robot mean power (W/kg, trial level), robot/human, and the
// human's hip / knee / ankle share of the sagittal leg joint power (mean |tau u| of left_/right_
// hip_flexion, knee, ankle_flexion; empty when the human model has no such joints). `synergies_files`
// supply the labels; the three lists are parallel.
void WritePowerRatioTable(const std::vector<std::string>& synergies_files,
                          const std::vector<std::string>& robot_metrics_files,
                          const std::vector<std::string>& human_metrics_files, const std::string& output,
                          const std::string& robot_name = "robot");

}  // namespace syn
