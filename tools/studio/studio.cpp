#include "tools/studio/studio.h"

#include <cmath>
#include <filesystem>
#include <sstream>

#include "common/error.h"
#include "common/sha256.h"
#include "stages/compose/compose_script.h"
#include "stages/compose/composer.h"
#include "stages/evaluate/evaluate.h"
#include "tools/studio/robot_description.h"

namespace syn {
namespace {

// JSON has no NaN: a metric that does not apply (no feet) is null.
nlohmann::json Number(double value) { return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr); }

nlohmann::json RangeJson(const RangeMetrics& metrics) {
  return {{"delta_p", Number(metrics.mean_delta_p)},
          {"delta_ke", Number(metrics.mean_delta_ke)},
          {"power_w_per_kg", Number(metrics.mean_power)},
          {"foot_sliding_ratio", Number(metrics.foot_sliding_ratio)},
          {"kinetic_energy", Number(metrics.mean_kinetic_energy)}};
}

}  // namespace

Studio::Studio(const std::string& library_path, const std::string& model_path, const std::string& robot_map_path,
               const StudioOptions& options)
    : options_(options), model_path_(model_path), model_(LoadModel(model_path, "auto")),
      library_(std::make_unique<LibraryReader>(library_path)) {
  const RobotMap map = LoadRobotMap(robot_map_path);
  robot_json_ = PlayerRobotDescription(model_path, model_, map);
  evaluator_ = std::make_unique<MotionEvaluator>(model_, FeetOnModel(map, model_), options_.eval_rate, options_.sliding);
  workspace_ = std::make_unique<Workspace>(model_);

  if (library_->velocityNames() != model_.velocityNames()) {
    throw DataError(Location::InFile(library_path), "the library's velocities are not those of " + model_path +
                                                        " (a library of another robot?)");
  }
  // The catalogue, once: a style's segments with their duration and σ (the sliders' scale).
  std::map<std::string, nlohmann::json> styles;
  for (const std::string& name : library_->synergyNames()) {
    const LibrarySynergy synergy = library_->read(name);
    const Eigen::VectorXd& sigma = synergy.segment.synergies.singular_values;
    segment_durations_[name] = synergy.segment.duration;
    nlohmann::json& style = styles[synergy.style];
    if (style.is_null()) style = {{"name", synergy.style}, {"segments", nlohmann::json::array()}};
    style["segments"].push_back({{"name", name},
                                 {"trial", synergy.trial},
                                 {"index", synergy.index},
                                 {"duration_s", synergy.segment.duration},
                                 {"sigma", std::vector<double>(sigma.data(), sigma.data() + sigma.size())}});
  }
  library_json_ = {{"library", library_path},
                   {"model", model_path},
                   {"robot", model_.name()},
                   {"limits", options_.ToJson()},
                   {"styles", nlohmann::json::array()}};
  for (auto& [name, style] : styles) library_json_["styles"].push_back(std::move(style));
}

nlohmann::json Studio::parse(const std::string& script_text, const std::string& file_name) const {
  const ComposeScript script = ParseComposeScript(script_text, file_name);
  nlohmann::json start = nullptr;
  if (!script.start_synergy.empty()) start = {{"synergy", script.start_synergy}};
  if (!script.start_motion.empty()) start = {{"motion", script.start_motion}, {"time", script.start_time}};
  nlohmann::json steps = nlohmann::json::array();
  for (const ComposeStep& step : script.steps) {
    nlohmann::json keyframes = nlohmann::json::array();
    for (const CoefficientKeyframe& keyframe : step.keyframes) {
      nlohmann::json entry = {{"at", keyframe.at}};
      if (keyframe.coefficients.empty()) entry["gain"] = keyframe.gains;
      else entry["coefficients"] = keyframe.coefficients;
      keyframes.push_back(entry);
    }
    steps.push_back({{"synergy", step.synergy},
                     {"line", step.line},
                     {"duration", step.duration ? nlohmann::json(*step.duration) : nlohmann::json(nullptr)},
                     {"repetitions", step.repetitions},
                     {"interpolation", InterpolationName(step.interpolation)},
                     {"blend", step.blend},
                     {"keyframes", keyframes}});
  }
  return {{"model", script.model},
          {"floating_base", script.floating_base},
          {"limit_scaling", script.scale_whole_step ? "step" : "joint"},
          {"start", start},
          {"steps", steps}};
}

nlohmann::json Studio::compose(const std::string& script_text, const std::string& file_name) const {
  const std::lock_guard<std::mutex> lock(mutex_);
  const ComposeScript script = ParseComposeScript(script_text, file_name);

  // The script must name the studio's robot, or what the page saves would compose differently in batch.
  std::error_code unreadable;
  const std::string script_model_sha = std::filesystem::is_regular_file(script.model, unreadable) ? Sha256OfFile(script.model) : "";
  if (script_model_sha != model_.sourceSha256()) {
    throw StudioLimitError(Location::InFile(file_name), "model = \"" + script.model + "\" is not the studio's robot (" +
                                                            model_path_ + "); name that file");
  }
  if (script.floating_base != "auto" && FloatingBaseFromName(script.floating_base) != model_.floatingBase()) {
    throw StudioLimitError(Location::InFile(file_name), "floating_base = \"" + script.floating_base +
                                                            "\" differs from the studio's model (" +
                                                            std::string(FloatingBaseName(model_.floatingBase())) + ")");
  }
  if (static_cast<int>(script.steps.size()) > options_.max_steps) {
    throw StudioLimitError(Location::AtLine(file_name, script.steps[static_cast<size_t>(options_.max_steps)].line),
                           "more than " + std::to_string(options_.max_steps) + " steps (--max-steps)");
  }
  int64_t pieces = 0;
  double seconds = 0;
  for (const ComposeStep& step : script.steps) {
    const auto known = segment_durations_.find(step.synergy);
    // An unknown synergy is the Composer's error (it lists what the library holds).
    const double duration = step.duration ? *step.duration : known != segment_durations_.end() ? known->second : 0.0;
    pieces += step.repetitions;
    seconds += step.repetitions * duration;
    if (pieces > options_.max_pieces) {
      throw StudioLimitError(Location::AtLine(file_name, step.line),
                             "more than " + std::to_string(options_.max_pieces) +
                                 " repetitions in all (--max-pieces): the studio composes short phrases");
    }
    if (seconds > options_.max_motion_seconds) {
      std::ostringstream message;
      message << "the motion would last more than " << options_.max_motion_seconds
              << " s by this step (--max-motion-seconds; compose long motions with syn-compose)";
      throw StudioLimitError(Location::AtLine(file_name, step.line), message.str());
    }
  }

  const Composer composer(script, *library_, model_, Composer::StartPose(script, *library_));
  const ComposedMotion composed = composer.compose();
  const MotionData& motion = composed.motion;
  const int64_t frames = motion.frames(), nq = motion.nq(), nu = motion.nu();

  // Metrics of the whole motion and of each step (from its first repetition to the next step).
  std::vector<TimeRange> ranges;
  nlohmann::json steps = nlohmann::json::array();
  for (size_t s = 0; s < composed.step_start_times.size(); ++s) {
    const double end = s + 1 < composed.step_start_times.size() ? composed.step_start_times[s + 1] : motion.time_s.back();
    ranges.push_back({composed.step_start_times[s], end});
    steps.push_back({{"start_s", composed.step_start_times[s]},
                     {"end_s", end},
                     {"synergy", script.steps[s].synergy},
                     {"line", script.steps[s].line},
                     {"scale", composed.step_scales.row(static_cast<Eigen::Index>(s)).minCoeff()}});
  }
  RangeMetrics whole;
  const std::vector<RangeMetrics> by_step =
      evaluator_->evaluate(motion.time_s, motion.q, motion.u, ranges, motion.time_s.front(), &whole);
  nlohmann::json metrics = RangeJson(whole);
  metrics["eval_rate"] = options_.eval_rate;
  metrics["steps"] = nlohmann::json::array();
  for (const RangeMetrics& range : by_step) metrics["steps"].push_back(RangeJson(range));

  // Per frame, for the plots: the generalized momentum's norm ‖A(q) u‖ and the kinetic energy ½ uᵀ A u
  // (Simbody's O(n) A·u; the only allocation per frame is the JSON row of q the page needs).
  std::vector<double> momentum(static_cast<size_t>(frames)), kinetic(static_cast<size_t>(frames));
  Eigen::VectorXd qk(nq), uk(nu), p(nu);
  nlohmann::json q = nlohmann::json::array();
  for (int64_t k = 0; k < frames; ++k) {
    qk = Eigen::Map<const Eigen::VectorXd>(&motion.q[static_cast<size_t>(k * nq)], nq);
    uk = Eigen::Map<const Eigen::VectorXd>(&motion.u[static_cast<size_t>(k * nu)], nu);
    workspace_->setQ(qk);
    workspace_->calcMassTimes(uk, p);
    momentum[static_cast<size_t>(k)] = p.norm();
    kinetic[static_cast<size_t>(k)] = 0.5 * uk.dot(p);
    q.push_back(std::vector<double>(qk.data(), qk.data() + nq));
  }
  metrics["series"] = {{"momentum", momentum}, {"kinetic_energy", kinetic}};

  // The Composer names the step of each warning ("file:line: step N (...)"): give the page its index.
  nlohmann::json warnings = nlohmann::json::array();
  for (const std::string& warning : composed.warnings) {
    int step = -1;
    for (size_t s = 0; s < script.steps.size() && step < 0; ++s) {
      const std::string prefix = file_name + ":" + std::to_string(script.steps[s].line) + ": step " + std::to_string(s + 1) + " (";
      if (warning.rfind(prefix, 0) == 0) step = static_cast<int>(s);
    }
    warnings.push_back({{"step", step}, {"message", warning}});
  }
  return {{"time", motion.time_s},
          {"coordinate_names", motion.coordinate_names},
          {"q", std::move(q)},
          {"steps", std::move(steps)},
          {"metrics", std::move(metrics)},
          {"warnings", std::move(warnings)}};
}

}  // namespace syn
