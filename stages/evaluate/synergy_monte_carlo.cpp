#include "stages/evaluate/synergy_monte_carlo.h"

#include <algorithm>
#include <cmath>

#include "common/motion_integration.h"
#include "common/random.h"
#include "common/row_major.h"
#include "stages/evaluate/worker_threads.h"

namespace syn {
namespace {

struct Spread {
  double mean = RangeMetrics::kNone, std = RangeMetrics::kNone;
};

Spread SpreadOf(const std::vector<RangeMetrics>& samples, double RangeMetrics::*field) {
  Spread spread;
  std::vector<double> values;
  for (const RangeMetrics& sample : samples) {
    if (std::isfinite(sample.*field)) values.push_back(sample.*field);
  }
  if (values.empty()) return spread;
  double sum = 0;
  for (double value : values) sum += value;
  spread.mean = sum / static_cast<double>(values.size());
  double squares = 0;
  for (double value : values) squares += (value - spread.mean) * (value - spread.mean);
  spread.std = values.size() > 1 ? std::sqrt(squares / static_cast<double>(values.size() - 1)) : 0.0;
  return spread;
}

nlohmann::json Number(double value) { return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr); }

double RelativeChange(double value, double reference) {
  return (std::isfinite(value) && std::isfinite(reference) && reference != 0) ? value / reference - 1.0
                                                                              : RangeMetrics::kNone;
}

}  // namespace

RangeMetrics EvaluateReconstruction(MotionEvaluator& evaluator, const Eigen::VectorXd& q0,
                                    const std::vector<double>& times, const Eigen::MatrixXd& velocities,
                                    bool heading_frame, double grid_origin, bool all_metrics) {
  const bool free_base = evaluator.model().hasFreeBase();
  Eigen::MatrixXd q, ground_velocities;
  IntegrateVelocities(free_base, q0, Eigen::Map<const Eigen::VectorXd>(times.data(), static_cast<Eigen::Index>(times.size())),
                      velocities, heading_frame ? BaseVelocityFrame::kHeading : BaseVelocityFrame::kGround, q,
                      ground_velocities);
  RangeMetrics whole;
  (void)evaluator.evaluate(times, RowMajorValues(q), RowMajorValues(ground_velocities), {}, grid_origin, &whole, all_metrics);
  return whole;
}

std::vector<MonteCarloSummary> RunMonteCarlo(std::span<MotionEvaluator> evaluators,
                                             const std::vector<MonteCarloSegment>& segments, bool heading_frame,
                                             double grid_origin, const MonteCarloOptions& options,
                                             const std::function<void(MotionEvaluator&)>& alongside) {
  // Each segment's tasks: the original (task 0), rank k (1), then the perturbed samples, with their
  // coefficients drawn here, in order, before anything runs.
  const int64_t per_segment = 2 + static_cast<int64_t>(std::max(0, options.samples));
  std::vector<std::vector<Eigen::VectorXd>> coefficients(segments.size());
  std::vector<MonteCarloSummary> summaries(segments.size());
  for (size_t s = 0; s < segments.size(); ++s) {
    const SegmentSynergies& pca = segments[s].segment->synergies;
    summaries[s].components = static_cast<int>(pca.components.rows());
    summaries[s].samples.resize(static_cast<size_t>(std::max(0, options.samples)));
    SplitMix64 random(options.seed * 0x9e3779b97f4a7c15ULL + static_cast<uint64_t>(segments[s].index));
    for (int n = 0; n < options.samples; ++n) {
      Eigen::VectorXd sample(pca.singular_values.size());
      for (Eigen::Index i = 0; i < sample.size(); ++i) {
        const double delta = options.alpha * (2.0 * random.uniform() - 1.0);
        sample[i] = pca.singular_values[i] * (1.0 + delta);
      }
      coefficients[s].push_back(std::move(sample));
    }
  }
  const int64_t first = alongside ? 1 : 0;
  RunTasks(first + per_segment * static_cast<int64_t>(segments.size()), static_cast<int>(evaluators.size()),
           [&](int worker, int64_t task) {
             if (task < first) {
               alongside(evaluators[static_cast<size_t>(worker)]);
               return;
             }
             task -= first;
             const size_t s = static_cast<size_t>(task / per_segment);
             const int64_t which = task % per_segment;
             const TrialSynergies::Segment& segment = *segments[s].segment;
             const SegmentSynergies& pca = segment.synergies;
             const Eigen::VectorXd q0 =
                 Eigen::Map<const Eigen::VectorXd>(segment.q0.data(), static_cast<Eigen::Index>(segment.q0.size()));
             MotionEvaluator& evaluator = evaluators[static_cast<size_t>(worker)];
             const std::vector<double>& times = segments[s].times;
             if (which == 0) {
               summaries[s].original =
                   EvaluateReconstruction(evaluator, q0, times, segment.velocities, heading_frame, grid_origin, true);
             } else if (which == 1) {
               summaries[s].rank_k = EvaluateReconstruction(evaluator, q0, times,
                                                            ReconstructVelocities(pca, pca.singular_values),
                                                            heading_frame, grid_origin, true);
             } else {
               const size_t n = static_cast<size_t>(which - 2);
               summaries[s].samples[n] = EvaluateReconstruction(
                   evaluator, q0, times, ReconstructVelocities(pca, coefficients[s][n]), heading_frame, grid_origin, false);
             }
           });
  return summaries;
}

MonteCarloSummary RunSegmentMonteCarlo(MotionEvaluator& evaluator, const TrialSynergies::Segment& segment,
                                       const std::vector<double>& times, bool heading_frame, double grid_origin,
                                       int64_t segment_index, const MonteCarloOptions& options) {
  return RunMonteCarlo(std::span<MotionEvaluator>(&evaluator, 1), {{&segment, times, segment_index}}, heading_frame,
                       grid_origin, options)
      .front();
}

nlohmann::json MonteCarloSummary::ToJson() const {
  nlohmann::json result;
  result["components"] = components;
  result["samples"] = samples.size();
  result["original"] = original.ToJson();
  result["rank_k"] = rank_k.ToJson();
  nlohmann::json spread;
  const std::pair<const char*, double RangeMetrics::*> fields[] = {
      {"mean_delta_p", &RangeMetrics::mean_delta_p},
      {"mean_delta_ke", &RangeMetrics::mean_delta_ke},
      {"mean_kinetic_energy", &RangeMetrics::mean_kinetic_energy}};
  for (const auto& [name, field] : fields) {
    const Spread value = SpreadOf(samples, field);
    spread[name] = {{"mean", Number(value.mean)},
                    {"std", Number(value.std)},
                    {"relative_change", Number(RelativeChange(value.mean, original.*field))},
                    {"rank_k_relative_change", Number(RelativeChange(rank_k.*field, original.*field))}};
  }
  result["perturbed"] = spread;
  return result;
}

}  // namespace syn
