// The paper's motion metrics, evaluated on a uniform grid (default 1 kHz, the
// paper's control rate) by cubic resampling of a sampled motion:
//
//   p_k = A(q_k) u_k           Simbody's O(n) A·u, never a formed matrix
//   KE_k = ½ u_kᵀ p_k
//   mean ΔP  = mean ‖p_k − p_{k−1}‖,  mean ΔKE = mean |KE_k − KE_{k−1}|
//   power_k = Σ_actuated |τ_i u_i| / total mass  (W/kg; τ by inverse dynamics from the resampled q, u, u̇,
//             so a reconstruction without stored torques is measured exactly like the original; the free
//             base's residual wrench and a virtual base chain are excluded)
//   foot sliding: common/foot_sliding.h
//
// The grid is absolute (origin + k / rate), so a segment evaluated on its own
// sees the same instants as inside its whole trial.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "common/model.h"
#include "common/foot_sliding.h"

namespace syn {

struct FootPoints {
  std::string side;
  int link = -1;
  std::vector<Eigen::Vector3d> sole_points;  // in the link frame
};

struct TimeRange {
  double start = 0, end = 0;  // s, both included
};

struct RangeMetrics {
  static constexpr double kNone = std::numeric_limits<double>::quiet_NaN();
  double start_s = 0, end_s = 0;
  int64_t eval_frames = 0;
  double mean_delta_p = kNone;         // N·m·s or N·s per step, whatever p's units per coordinate
  double mean_delta_ke = kNone;        // J per step
  double mean_kinetic_energy = kNone;  // J
  double mean_power = kNone;           // W/kg
  double foot_sliding_ratio = kNone;   // NaN without feet
  std::vector<double> power_by_velocity;  // [nu] W/kg, mean |τ_i u_i| / mass (whole span only)

  nlohmann::json ToJson() const;
};

// How p = A(q) u, the inverse dynamics and the foot poses are computed at each grid point. Both give the same numbers to rounding (the model tests
// hold them to 1e-12, the evaluate tests the metrics of real trials to 1e-9); kTree is several times faster.
enum class MomentumOperator {
  kTree,     // Workspace::calcMassTimesAt (and calcDynamicsAt where power and feet are needed): recursive
             // passes over the tree, no Simbody realisation
  kSimbody,  // Workspace::setQ, calcMassTimes (Simbody's multiplyByM), setU, calcInverseDynamics and
             // findLinkPose: the straightforward reference path
};

class MotionEvaluator {
 public:
  MotionEvaluator(const Model& model, std::vector<FootPoints> feet, double eval_rate, const FootSlidingOptions& sliding,
                  MomentumOperator momentum = MomentumOperator::kTree);

  const Model& model() const { return workspace_.model(); }
  double evalRate() const { return eval_rate_; }

  // A motion sampled at `time` [T] (T ≥ 2): q [T, nq] and ground-frame u [T, nu], row-major. Returns the
  // metrics of each range (sorted, non-overlapping) and, in `whole`, of the full time span. Without
  // `all_metrics` only ΔP, ΔKE and KE are computed (positions-only Simbody work, about half the cost):
  // what the Monte-Carlo samples need.
  std::vector<RangeMetrics> evaluate(const std::vector<double>& time, const std::vector<double>& q,
                                     const std::vector<double>& u, const std::vector<TimeRange>& ranges,
                                     double grid_origin, RangeMetrics* whole, bool all_metrics = true);

 private:
  Workspace workspace_;
  MomentumOperator momentum_;
  std::vector<FootPoints> feet_;
  double eval_rate_;
  FootSlidingOptions sliding_;
  std::vector<bool> actuated_;
};

}  // namespace syn
