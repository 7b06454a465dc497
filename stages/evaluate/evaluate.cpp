#include "stages/evaluate/evaluate.h"

#include <cmath>
#include <sstream>

#include "common/error.h"
#include "common/percentile.h"
#include "stages/evaluate/worker_threads.h"

namespace syn {
namespace {

nlohmann::json Number(double value) { return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr); }

double MeanOf(const std::vector<double>& values) {
  if (values.empty()) return RangeMetrics::kNone;
  double sum = 0;
  for (double value : values) sum += value;
  return sum / static_cast<double>(values.size());
}

// Whether the synergies' velocities are the motion's (all) and the segments lie inside it.
bool CheckSynergiesBelong(const MotionData& motion, const TrialSynergies& synergies, const std::string& path) {
  for (size_t s = 0; s < synergies.segments.size(); ++s) {
    const TrialSynergies::Segment& segment = synergies.segments[s];
    if (segment.start_frame < 0 || segment.end_frame > motion.frames() || segment.end_frame - segment.start_frame < 2) {
      throw DataError(Location::InFile(path), "segment " + std::to_string(s) + " (frames " +
                                                  std::to_string(segment.start_frame) + ".." +
                                                  std::to_string(segment.end_frame) + ") does not lie inside the motion's " +
                                                  std::to_string(motion.frames()) + " frames");
    }
    const double* q = &motion.q[static_cast<size_t>(segment.start_frame * motion.nq())];
    for (int64_t i = 0; i < motion.nq(); ++i) {
      if (static_cast<int64_t>(segment.q0.size()) != motion.nq() || segment.q0[static_cast<size_t>(i)] != q[i]) {
        throw DataError(Location::InFile(path), "segment " + std::to_string(s) +
                                                    ": q0 differs from the motion at frame " +
                                                    std::to_string(segment.start_frame) +
                                                    " (synergies of another motion?)");
      }
    }
  }
  return synergies.velocity_names == motion.velocity_names;
}

}  // namespace

bool EvaluateOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& message) {
    if (error) *error = message;
    return false;
  };
  if (!(eval_rate > 0)) return fail("--eval-rate must be positive");
  if (!(sliding.contact_height >= 0)) return fail("--contact-height must be >= 0");
  if (!(sliding.slide_speed >= 0)) return fail("--slide-speed must be >= 0");
  if (!(sliding.window >= 0)) return fail("--slide-window must be >= 0");
  if (!(sliding.penetration >= 0)) return fail("--penetration must be >= 0");
  if (monte_carlo.samples < 0) return fail("--samples must be >= 0");
  if (threads < 0) return fail("--threads must be >= 0 (0: the default)");
  if (!(monte_carlo.alpha >= 0 && monte_carlo.alpha < 1)) return fail("--alpha must lie in [0, 1)");
  return true;
}

nlohmann::json EvaluateOptions::ToJson() const {
  return {{"eval_rate", eval_rate},
          {"contact_height", sliding.contact_height},
          {"slide_speed", sliding.slide_speed},
          {"slide_window", sliding.window},
          {"penetration", sliding.penetration},
          {"samples", monte_carlo.samples},
          {"alpha", monte_carlo.alpha},
          {"seed", monte_carlo.seed}};
}

std::vector<FootPoints> FeetOnModel(const RobotMap& map, const Model& model) {
  std::vector<FootPoints> feet;
  for (const RobotFoot& foot : map.feet) {
    FootPoints points;
    points.side = foot.side;
    points.link = model.findLinkIndex(foot.link);
    if (points.link < 0) {
      throw DataError(Location::AtLine(map.file, foot.line),
                      "foot link '" + foot.link + "' is not a link of " + model.name());
    }
    for (const auto& point : foot.sole_points) points.sole_points.emplace_back(point[0], point[1], point[2]);
    if (points.sole_points.empty()) {
      throw DataError(Location::AtLine(map.file, foot.line), "foot '" + foot.side + "' has no sole_points");
    }
    feet.push_back(std::move(points));
  }
  return feet;
}

namespace {

// What syn-retarget's contact forces leave of the base's residual wrench (motion_file.h): magnitude of
// the force (N) and moment (N·m, about the centre of mass) over the stored frames, and the mean vertical
// contact force as a fraction of body weight.
nlohmann::json UnexplainedResidual(const MotionData& motion, double gravity) {
  std::vector<double> force, moment;
  double vertical = 0;
  const size_t feet = motion.contact_feet.size();
  for (int64_t t = 0; t < motion.frames(); ++t) {
    const double* wrench = &motion.unexplained_wrench[static_cast<size_t>(t) * 6];
    moment.push_back(std::hypot(wrench[0], wrench[1], wrench[2]));
    force.push_back(std::hypot(wrench[3], wrench[4], wrench[5]));
    for (size_t f = 0; f < feet; ++f) vertical += motion.contact_force[(static_cast<size_t>(t) * feet + f) * 3 + 2];
  }
  const double weight = motion.total_mass * gravity * static_cast<double>(motion.frames());
  return {{"mean_unexplained_force_n", Number(MeanOf(force))},
          {"p95_unexplained_force_n", Number(NearestRankPercentile(force, 0.95))},
          {"mean_unexplained_moment_nm", Number(MeanOf(moment))},
          {"p95_unexplained_moment_nm", Number(NearestRankPercentile(moment, 0.95))},
          {"mean_vertical_contact_force_per_weight", Number(weight > 0 ? vertical / weight : std::nan(""))}};
}

}  // namespace

nlohmann::json EvaluateMotion(const MotionData& motion, const Model& model, const std::vector<FootPoints>& feet,
                              const TrialSynergies* synergies, const EvaluateOptions& options,
                              const std::string& synergies_path) {
  CheckMotionMatchesModel(motion, model);
  if (motion.frames() < 2) throw DataError(Location::InFile("motion"), "needs at least 2 frames to evaluate");
  MotionEvaluator evaluator(model, feet, options.eval_rate, options.sliding, options.momentum);
  const double origin = motion.time_s.front();

  std::vector<TimeRange> ranges;
  bool all_velocities = false;
  if (synergies) {
    all_velocities = CheckSynergiesBelong(motion, *synergies, synergies_path);
    for (const TrialSynergies::Segment& segment : synergies->segments) {
      ranges.push_back({motion.time_s[static_cast<size_t>(segment.start_frame)],
                        motion.time_s[static_cast<size_t>(segment.end_frame - 1)]});
    }
  }
  const bool heading_frame = model.hasFreeBase();
  const bool monte_carlo = synergies && all_velocities && options.monte_carlo.samples >= 0;
  RangeMetrics whole;
  std::vector<RangeMetrics> stored;
  auto evaluate_stored = [&](MotionEvaluator& on) {
    stored = on.evaluate(motion.time_s, motion.q, motion.u, ranges, origin, &whole);
  };
  std::vector<MonteCarloSummary> summaries;
  if (monte_carlo) {
    std::vector<MonteCarloSegment> inputs;
    for (size_t s = 0; s < synergies->segments.size(); ++s) {
      const TrialSynergies::Segment& segment = synergies->segments[s];
      inputs.push_back({&segment,
                        std::vector<double>(motion.time_s.begin() + segment.start_frame,
                                            motion.time_s.begin() + segment.end_frame),
                        static_cast<int64_t>(s)});
    }
    // One evaluator per thread; the trial's own metrics run as one more task beside the reconstructions.
    const int threads = options.threads > 0 ? options.threads : DefaultThreadCount();
    std::vector<MotionEvaluator> evaluators;
    evaluators.push_back(std::move(evaluator));
    for (int t = 1; t < threads; ++t) evaluators.emplace_back(model, feet, options.eval_rate, options.sliding, options.momentum);
    summaries = RunMonteCarlo(evaluators, inputs, heading_frame, origin, options.monte_carlo, evaluate_stored);
  } else {
    evaluate_stored(evaluator);
  }

  nlohmann::json result;
  result["schema"] = kMetricsSchema;
  result["schema_version"] = kMetricsSchemaVersion;
  result["parameters"] = options.ToJson();
  result["model"] = {{"name", model.name()},
                     {"sha256", model.sourceSha256()},
                     {"total_mass_kg", model.totalMass()},
                     {"floating_base", std::string(FloatingBaseName(model.floatingBase()))},
                     {"feet", feet.size()}};
  result["motion"] = {{"frames", motion.frames()}, {"duration_s", motion.time_s.back() - motion.time_s.front()}};
  result["trial"] = whole.ToJson();
  // Where the power goes: every velocity's mean |τ_i u_i| per kilogram (unactuated ones included, marked).
  nlohmann::json by_velocity = nlohmann::json::object();
  for (size_t v = 0; v < whole.power_by_velocity.size(); ++v) {
    by_velocity[model.velocityNames()[v] + (model.actuatedVelocities()[v] ? "" : " (unactuated)")] =
        whole.power_by_velocity[v];
  }
  result["trial"]["power_by_velocity_w_per_kg"] = by_velocity;
  if (!motion.unexplained_wrench.empty()) result["trial"]["base_residual"] = UnexplainedResidual(motion, model.gravity());
  result["segments"] = nlohmann::json::array();
  if (!synergies) return result;

  std::vector<double> dp_change, dke_change, dp_rank_k, dke_rank_k;
  for (size_t s = 0; s < synergies->segments.size(); ++s) {
    const TrialSynergies::Segment& segment = synergies->segments[s];
    nlohmann::json entry = {{"index", s},
                            {"start_frame", segment.start_frame},
                            {"end_frame", segment.end_frame},
                            {"stored", stored[s].ToJson()}};
    if (monte_carlo) {
      entry["monte_carlo"] = summaries[s].ToJson();
      const nlohmann::json& perturbed = entry["monte_carlo"]["perturbed"];
      auto collect = [](const nlohmann::json& value, std::vector<double>& into) {
        if (value.is_number()) into.push_back(value.get<double>());
      };
      collect(perturbed["mean_delta_p"]["relative_change"], dp_change);
      collect(perturbed["mean_delta_ke"]["relative_change"], dke_change);
      collect(perturbed["mean_delta_p"]["rank_k_relative_change"], dp_rank_k);
      collect(perturbed["mean_delta_ke"]["rank_k_relative_change"], dke_rank_k);
    }
    result["segments"].push_back(entry);
  }
  if (monte_carlo) {
    result["monte_carlo"] = {{"segments", synergies->segments.size()},
                             {"mean_relative_change_delta_p", Number(MeanOf(dp_change))},
                             {"mean_relative_change_delta_ke", Number(MeanOf(dke_change))},
                             {"mean_rank_k_relative_change_delta_p", Number(MeanOf(dp_rank_k))},
                             {"mean_rank_k_relative_change_delta_ke", Number(MeanOf(dke_rank_k))}};
  } else {
    result["monte_carlo"] = {{"skipped", "the synergies hold joint velocities only (--velocities joints): a "
                                         "reconstruction needs the base velocities too"}};
  }
  return result;
}

std::string SegmentMetricsCsv(const nlohmann::json& metrics) {
  std::ostringstream text;
  text.precision(17);
  text << "segment,start_frame,end_frame,start_s,end_s,mean_delta_p,mean_delta_ke,mean_kinetic_energy,"
          "mean_power_w_per_kg,foot_sliding_ratio,mc_components,mc_original_delta_p,mc_rank_k_delta_p,"
          "mc_perturbed_delta_p_mean,mc_perturbed_delta_p_std,mc_original_delta_ke,mc_rank_k_delta_ke,"
          "mc_perturbed_delta_ke_mean,mc_perturbed_delta_ke_std\n";
  auto cell = [&](const nlohmann::json& value) {
    if (value.is_number()) text << value.get<double>();
  };
  for (const nlohmann::json& segment : metrics["segments"]) {
    const nlohmann::json& stored = segment["stored"];
    text << segment["index"].get<int64_t>() << ',' << segment["start_frame"].get<int64_t>() << ','
         << segment["end_frame"].get<int64_t>();
    for (const char* key : {"start_s", "end_s", "mean_delta_p", "mean_delta_ke", "mean_kinetic_energy",
                            "mean_power_w_per_kg", "foot_sliding_ratio"}) {
      text << ',';
      cell(stored[key]);
    }
    if (segment.contains("monte_carlo")) {
      const nlohmann::json& mc = segment["monte_carlo"];
      text << ',' << mc["components"].get<int64_t>();
      for (const char* key : {"mean_delta_p", "mean_delta_ke"}) {
        text << ',';
        cell(mc["original"][key]);
        text << ',';
        cell(mc["rank_k"][key]);
        text << ',';
        cell(mc["perturbed"][key]["mean"]);
        text << ',';
        cell(mc["perturbed"][key]["std"]);
      }
    } else {
      text << ",,,,,,,,,";
    }
    text << '\n';
  }
  return text.str();
}

}  // namespace syn
