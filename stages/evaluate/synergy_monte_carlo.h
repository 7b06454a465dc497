// The paper's Monte-Carlo test of synergy reconstructions (DESIGN.md, Method:
// Metrics): per segment, N reconstructions û = mean + Σ a_i U_i V_i with
// a_i = σ_i (1 + δ_i), δ ~ U(−α, α)^k, each integrated from the segment's q0
// and evaluated like the original.
//
// "The original" here is the segment's own velocity samples (as the PCA saw
// them) integrated from q0 by the same integrator: the comparison then
// isolates what the synergy truncation and the perturbation change, not the
// difference between the retargeter's q and the integral of its u. (The
// stored motion's own segment metrics are reported beside it.)
//
// The original and the rank-k reconstruction get every metric; the perturbed
// samples ΔP̄ and ΔK̄E only (what the paper reports), at half the cost.
//
// Random numbers come from splitmix64 seeded with (seed, segment index) and
// turned into doubles by bit arithmetic, so the same seed gives the same
// numbers on every platform and in any segment order. The coefficients are
// drawn before any reconstruction runs, and each reconstruction is evaluated
// on its own by whichever thread takes it, so the numbers do not depend on
// the number of threads either.
#pragma once

#include <cstdint>
#include <functional>
#include <span>
#include <vector>

#include <nlohmann/json.hpp>

#include "stages/evaluate/motion_metrics.h"
#include "common/synergies_file.h"

namespace syn {

struct MonteCarloOptions {
  int samples = 100;    // paper: 100
  double alpha = 0.2;   // paper: ±20 %
  uint64_t seed = 1;
};

struct MonteCarloSummary {
  RangeMetrics original;           // the segment's velocity samples, integrated
  RangeMetrics rank_k;             // a_i = σ_i, the k synergies in the file
  std::vector<RangeMetrics> samples;
  int components = 0;

  nlohmann::json ToJson() const;
};

struct MonteCarloSegment {
  const TrialSynergies::Segment* segment = nullptr;
  std::vector<double> times;  // the motion's frame times of the segment [start_frame, end_frame)
  int64_t index = 0;          // the segment's index in its trial: seeds its random numbers
};

// Every segment's original, rank-k and perturbed reconstructions, spread over `evaluators` (one thread
// each; all on the same model and options). `heading_frame`: the segments' base velocities are in the
// pelvis heading frame (synergies of all velocities on a free base). One summary per segment, in order.
// `alongside`, when given, runs first as one more task on one of the evaluators (syn-evaluate's whole-trial
// metrics), so it overlaps the reconstructions instead of preceding them.
[[nodiscard]] std::vector<MonteCarloSummary> RunMonteCarlo(
    std::span<MotionEvaluator> evaluators, const std::vector<MonteCarloSegment>& segments, bool heading_frame,
    double grid_origin, const MonteCarloOptions& options,
    const std::function<void(MotionEvaluator&)>& alongside = nullptr);

// One segment on one thread. `times`: the motion's frame times of the segment [start_frame, end_frame).
[[nodiscard]] MonteCarloSummary RunSegmentMonteCarlo(MotionEvaluator& evaluator, const TrialSynergies::Segment& segment,
                                                     const std::vector<double>& times, bool heading_frame,
                                                     double grid_origin, int64_t segment_index,
                                                     const MonteCarloOptions& options);

// The velocities û integrated from q0 and evaluated over their whole span (see MotionEvaluator::evaluate
// for `all_metrics`).
[[nodiscard]] RangeMetrics EvaluateReconstruction(MotionEvaluator& evaluator, const Eigen::VectorXd& q0,
                                                  const std::vector<double>& times, const Eigen::MatrixXd& velocities,
                                                  bool heading_frame, double grid_origin, bool all_metrics);

}  // namespace syn
