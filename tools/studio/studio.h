// The studio's work, without HTTP (tools/studio/studio_server.h serves it): the library's catalogue, the
// robot for the 3-D player, and compose + metrics of a script's text with the very code syn-compose
// (stages/compose: ParseComposeScript, Composer) and syn-evaluate (stages/evaluate: MotionEvaluator) run,
// so that a script saved from the page composes to the same motion in batch.
//
// Every composition is bounded before it starts (StudioOptions: steps, Σ repetitions, Σ repetitions ×
// duration), so no request can keep the server busy for long. Requests are served one at a time: the
// library reader (HDF5) and the evaluator's Simbody workspace are not shared between threads, and two cores
// gain nothing from composing in parallel.
#pragma once

#include <map>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/error.h"
#include "common/library_file.h"
#include "common/model.h"
#include "common/robot_map.h"
#include "stages/evaluate/motion_metrics.h"
#include "tools/studio/studio_options.h"

namespace syn {

// A script the studio will not compose (a bound exceeded, another robot): HTTP 400 like a DataError.
class StudioLimitError : public DataError {
 public:
  using DataError::DataError;
};

class Studio {
 public:
  // Throws DataError for a bad library, model or robot map (the tool exits 1 before serving).
  Studio(const std::string& library_path, const std::string& model_path, const std::string& robot_map_path,
         const StudioOptions& options);

  const StudioOptions& options() const { return options_; }
  // What the URDF needed forgiving (Model::warnings()), for the tool to print once.
  const std::vector<std::string>& modelWarnings() const { return model_.warnings(); }
  // GET /api/library: the model path scripts name, and per style its segments with duration and σ.
  const nlohmann::json& library() const { return library_json_; }
  // GET /api/robot: tools/report/player.js's robot description.
  const nlohmann::json& robot() const { return robot_json_; }

  // POST /api/parse: the script's TOML as the page edits it: {model, floating_base, limit_scaling,
  // start: {synergy} | {motion, time} | null, steps: [{synergy, line, duration (null: the segment's own),
  // repetitions, interpolation, blend, keyframes: [{at, gain | coefficients}]}]} (a step's constant
  // coefficients are its one keyframe at 0, as the Composer reads them). Throws DataError like compose.
  [[nodiscard]] nlohmann::json parse(const std::string& script_text, const std::string& file_name) const;

  // POST /api/compose: the script's TOML (errors located at `file_name`:line) composed and evaluated:
  //   {time [T], q [T][nq], coordinate_names, steps: [{start_s, end_s, synergy, line}],
  //    metrics: {delta_p, delta_ke, power_w_per_kg, foot_sliding_ratio, kinetic_energy, eval_rate,
  //              steps: [{delta_p, delta_ke, power_w_per_kg, foot_sliding_ratio}],
  //              series: {momentum [T] = ‖A(q) u‖, kinetic_energy [T]}},
  //    warnings: [{step (0-based, -1: none), message}]}.
  // Throws DataError (also StudioLimitError) for a script that cannot be composed.
  [[nodiscard]] nlohmann::json compose(const std::string& script_text, const std::string& file_name) const;

 private:
  StudioOptions options_;
  std::string model_path_;
  Model model_;
  std::unique_ptr<LibraryReader> library_;
  nlohmann::json library_json_, robot_json_;
  std::map<std::string, double> segment_durations_;  // "STYLE/TRIAL/SEGMENT" -> s
  mutable std::mutex mutex_;
  mutable std::unique_ptr<MotionEvaluator> evaluator_;
  mutable std::unique_ptr<Workspace> workspace_;
};

}  // namespace syn
