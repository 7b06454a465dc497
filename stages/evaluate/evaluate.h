// syn-evaluate: the paper's metrics for one motion — per trial, per segment
// (the segments of its synergies file) and, with synergies, the Monte-Carlo
// reconstructions — as one JSON document (schema synsculpt.metrics v1) and
// optionally one CSV row per segment.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/model.h"
#include "common/motion_file.h"
#include "stages/evaluate/motion_metrics.h"
#include "stages/evaluate/synergy_monte_carlo.h"
#include "common/robot_map.h"

namespace syn {

inline constexpr const char* kMetricsSchema = "synsculpt.metrics";
inline constexpr int kMetricsSchemaVersion = 1;

struct EvaluateOptions {
  double eval_rate = 1000.0;  // Hz: the paper's control rate
  FootSlidingOptions sliding;
  MonteCarloOptions monte_carlo;
  // Worker threads for the reconstructions; 0 = DefaultThreadCount() (stages/evaluate/worker_threads.h:
  // SYN_THREADS, else the cores `make -jN` leaves, else every core). An execution setting, not a
  // parameter: the output is byte-identical for any count, so it is not in ToJson().
  int threads = 0;
  // The reference path for tests and benchmarks (motion_metrics.h); same numbers to rounding.
  MomentumOperator momentum = MomentumOperator::kTree;

  bool IsValid(std::string* error) const;
  nlohmann::json ToJson() const;
};

// The feet of a robot map on a model; a foot link missing from the model is a DataError at the map's line.
[[nodiscard]] std::vector<FootPoints> FeetOnModel(const RobotMap& map, const Model& model);

// `synergies` may be null (trial metrics only). Throws DataError when the synergies do not belong to the motion.
[[nodiscard]] nlohmann::json EvaluateMotion(const MotionData& motion, const Model& model,
                                            const std::vector<FootPoints>& feet, const TrialSynergies* synergies,
                                            const EvaluateOptions& options, const std::string& synergies_path);

// One row per segment: trial metrics are in the JSON; this is the table a spreadsheet wants.
[[nodiscard]] std::string SegmentMetricsCsv(const nlohmann::json& metrics);

}  // namespace syn
