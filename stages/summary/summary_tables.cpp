#include "stages/summary/summary_tables.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <initializer_list>
#include <fstream>
#include <sstream>
#include <utility>
#include <unistd.h>

#include "common/error.h"
#include "common/file_bytes.h"

#include <nlohmann/json.hpp>
#include "common/synergies_file.h"

namespace syn {
namespace {

std::string Number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", value);
  return text;
}

// CSV cell: quoted when it holds a comma or a quote.
std::string Cell(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string quoted(1, '"');
  for (char c : text) {
    quoted.push_back(c);
    if (c == '"') quoted.push_back('"');
  }
  quoted.push_back('"');
  return quoted;
}

// Cells of `keys` from a JSON object, each after a comma (empty when the object, the key or a number is absent).
std::string Cells(const nlohmann::json* object, std::initializer_list<const char*> keys) {
  std::ostringstream cells;
  for (const char* key : keys) {
    cells << ',';
    if (object && object->contains(key) && (*object)[key].is_number()) cells << Number((*object)[key].get<double>());
  }
  return cells.str();
}

// Metric cells from a syn-evaluate JSON object (empty when absent or null).
std::string MetricCells(const nlohmann::json* metrics, const nlohmann::json* monte_carlo) {
  return Cells(metrics, {"mean_delta_p", "mean_delta_ke", "mean_power_w_per_kg", "foot_sliding_ratio"}) +
         Cells(monte_carlo, {"rank_k_delta_p", "rank_k_delta_ke"});
}

nlohmann::json ReadMetrics(const std::string& path) {
  try {
    return nlohmann::json::parse(ReadFileText(path));
  } catch (const nlohmann::json::exception& error) {
    throw DataError(Location::InFile(path), std::string("not syn-evaluate JSON: ") + error.what());
  }
}

// The trial-level mean power (W/kg) of a syn-evaluate JSON.
double TrialPower(const nlohmann::json& metrics, const std::string& path) {
  if (!metrics.contains("trial") || !metrics["trial"].contains("mean_power_w_per_kg") ||
      !metrics["trial"]["mean_power_w_per_kg"].is_number()) {
    throw DataError(Location::InFile(path), "has no trial.mean_power_w_per_kg (was the motion evaluated with its model?)");
  }
  return metrics["trial"]["mean_power_w_per_kg"].get<double>();
}

// The human's sagittal leg joint power (W/kg, both legs) from syn-evaluate's per-velocity breakdown,
// when the model names its joints as syn-human does (left_/right_ hip_flexion, knee, ankle_flexion):
// the joints whose share of the leg's power the biomechanics literature reports.
struct SagittalLegPower {
  double hip = 0, knee = 0, ankle = 0;
  bool complete = false;  // all six velocities found
};

SagittalLegPower SagittalLegPowerOf(const nlohmann::json& metrics) {
  SagittalLegPower legs;
  if (!metrics.contains("trial") || !metrics["trial"].contains("power_by_velocity_w_per_kg")) return legs;
  const nlohmann::json& by_velocity = metrics["trial"]["power_by_velocity_w_per_kg"];
  int found = 0;
  for (const char* side : {"left_", "right_"}) {
    for (auto [joint, sum] : {std::pair<const char*, double*>{"hip_flexion", &legs.hip}, {"knee", &legs.knee},
                              {"ankle_flexion", &legs.ankle}}) {
      const std::string name = std::string(side) + joint;
      if (by_velocity.contains(name) && by_velocity[name].is_number()) {
        *sum += by_velocity[name].get<double>();
        ++found;
      }
    }
  }
  legs.complete = found == 6;
  return legs;
}

// What the retargeted motion's contact forces leave of the base's residual (syn-evaluate's
// trial.base_residual, present when the motion has them): mean force N and moment N·m.
constexpr const char* kResidualColumns = ",unexplained_residual_force_n,unexplained_residual_moment_nm";

std::string ResidualCells(const nlohmann::json& metrics) {
  const nlohmann::json* residual =
      metrics.contains("trial") && metrics["trial"].contains("base_residual") ? &metrics["trial"]["base_residual"] : nullptr;
  return Cells(residual, {"mean_unexplained_force_n", "mean_unexplained_moment_nm"});
}

constexpr const char* kMetricColumns =
    ",mean_delta_p,mean_delta_ke,mean_power_w_per_kg,foot_sliding_ratio,rank_k_change_delta_p,rank_k_change_delta_ke";

}  // namespace

void WriteSummaryTable(const std::vector<std::string>& synergies_files, const std::vector<std::string>& metrics_files,
                       const std::string& table, const std::string& output) {
  if (!metrics_files.empty() && metrics_files.size() != synergies_files.size()) {
    throw UsageError("give one metrics file per synergies file, in the same order");
  }
  // (Rows are built with a stream: GCC 12 warns falsely on chains of std::string operator+.)
  std::ostringstream text;
  if (table == "trials") {
    text << "trial,subject,style,motion_class,segments,duration_s,mean_segment_duration_s,"
            "variance_explained_by_kept_synergies,median_components_for_90_percent"
         << (metrics_files.empty() ? "" : kMetricColumns) << (metrics_files.empty() ? "" : kResidualColumns) << "\n";
  } else if (table == "segments") {
    text << "trial,style,motion_class,segment,start_frame,end_frame,duration_s,pc1_ratio,pc2_ratio,pc3_ratio,"
            "variance_explained_by_kept_synergies,components_for_90_percent"
         << (metrics_files.empty() ? "" : kMetricColumns) << "\n";
  } else {
    throw UsageError("--table must be trials or segments");
  }
  for (size_t f = 0; f < synergies_files.size(); ++f) {
    const std::string& file = synergies_files[f];
    const nlohmann::json metrics = metrics_files.empty() ? nlohmann::json() : ReadMetrics(metrics_files[f]);
    SynergyLabels labels;
    const TrialSynergies trial = ReadTrialSynergies(file, &labels);
    double duration = 0, explained = 0;
    std::vector<int> k90;
    for (size_t s = 0; s < trial.segments.size(); ++s) {
      const auto& segment = trial.segments[s];
      const auto& ratio = segment.synergies.explained_variance_ratio;
      duration += segment.duration;
      explained += ratio.sum();
      k90.push_back(segment.synergies.components_for_90_percent);
      if (table == "segments") {
        text << Cell(labels.trial) << ',' << Cell(labels.style) << ',' << Cell(labels.motion_class) << ',' << s << ','
             << segment.start_frame << ',' << segment.end_frame << ',' << Number(segment.duration);
        for (int k = 0; k < 3; ++k) text << ',' << (k < ratio.size() ? Number(ratio[k]) : std::string());
        text << ',' << Number(ratio.sum()) << ',' << segment.synergies.components_for_90_percent;
        if (!metrics_files.empty()) {
          const nlohmann::json* row = nullptr;
          nlohmann::json changes;
          if (metrics.contains("segments") && s < metrics["segments"].size()) {
            const nlohmann::json& entry = metrics["segments"][s];
            row = &entry["stored"];
            if (entry.contains("monte_carlo")) {
              changes["rank_k_delta_p"] = entry["monte_carlo"]["perturbed"]["mean_delta_p"]["rank_k_relative_change"];
              changes["rank_k_delta_ke"] = entry["monte_carlo"]["perturbed"]["mean_delta_ke"]["rank_k_relative_change"];
            }
          }
          text << MetricCells(row, &changes);
        }
        text << '\n';
      }
    }
    if (table == "trials") {
      const double count = static_cast<double>(trial.segments.size());
      std::sort(k90.begin(), k90.end());
      text << Cell(labels.trial) << ',' << Cell(labels.subject) << ',' << Cell(labels.style) << ','
           << Cell(labels.motion_class) << ',' << trial.segments.size() << ',' << Number(duration) << ','
           << Number(count > 0 ? duration / count : 0) << ',' << Number(count > 0 ? explained / count : 0) << ','
           << (k90.empty() ? std::string() : std::to_string(k90[k90.size() / 2]));
      if (!metrics_files.empty()) {
        nlohmann::json changes;
        if (metrics.contains("monte_carlo")) {
          changes["rank_k_delta_p"] = metrics["monte_carlo"].value("mean_rank_k_relative_change_delta_p", nlohmann::json());
          changes["rank_k_delta_ke"] = metrics["monte_carlo"].value("mean_rank_k_relative_change_delta_ke", nlohmann::json());
        }
        text << MetricCells(metrics.contains("trial") ? &metrics["trial"] : nullptr, &changes);
        text << ResidualCells(metrics);
      }
      text << '\n';
    }
  }
  WriteFileAtomically(output, text.str());
}

void WritePowerRatioTable(const std::vector<std::string>& synergies_files,
                          const std::vector<std::string>& robot_metrics_files,
                          const std::vector<std::string>& human_metrics_files, const std::string& output,
                          const std::string& robot_name) {
  if (robot_metrics_files.size() != synergies_files.size() || human_metrics_files.size() != synergies_files.size()) {
    throw UsageError("give one robot and one human metrics file per synergies file, in the same order");
  }
  if (robot_name.empty() || robot_name.find_first_of(",\"\n") != std::string::npos) {
    throw UsageError("--robot-name must be a plain name");
  }
  std::ostringstream text;
  text << "trial,subject,motion_class,robot,human_w_per_kg,robot_w_per_kg,robot_over_human,"
          "human_hip_share,human_knee_share,human_ankle_share\n";
  for (size_t f = 0; f < synergies_files.size(); ++f) {
    SynergyLabels labels;
    (void)ReadTrialSynergies(synergies_files[f], &labels);
    const double robot = TrialPower(ReadMetrics(robot_metrics_files[f]), robot_metrics_files[f]);
    const nlohmann::json human_metrics = ReadMetrics(human_metrics_files[f]);
    const double human = TrialPower(human_metrics, human_metrics_files[f]);
    text << Cell(labels.trial) << ',' << Cell(labels.subject) << ',' << Cell(labels.motion_class) << ','
         << robot_name << ',' << Number(human) << ',' << Number(robot) << ','
         << (human > 0 ? Number(robot / human) : std::string());
    const SagittalLegPower legs = SagittalLegPowerOf(human_metrics);
    const double total = legs.hip + legs.knee + legs.ankle;
    for (double joint : {legs.hip, legs.knee, legs.ankle}) {
      text << ',' << (legs.complete && total > 0 ? Number(joint / total) : std::string());
    }
    text << '\n';
  }
  WriteFileAtomically(output, text.str());
}

}  // namespace syn
