// Momentum segmentation (paper, "Postural Synergies ... in SynSculptor"): a
// new motion primitive starts where the generalized momentum jumps.
//
//   p(t_i) = A(q(t_i)) u(t_i)      at the analysis instants t_i (default 100 Hz, as the paper's Fig. 3),
//                                  q and u linear between frames (Simbody's O(n) A·u; A is never formed)
//   ΔP(t_i) = ‖p(t_i) − p(t_{i−1})‖
//   boundary where ΔP > ΔP_th and at least min_duration after the previous one
//
// ΔP_th's meaning depends on the robot's mass and on the analysis rate (a
// jump spreads over more samples at a higher rate): --threshold-quantile
// gives a scale-free alternative.
#pragma once

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "common/model.h"
#include "common/motion_file.h"
#include "common/segments_file.h"

namespace syn {

enum class MomentumKind {
  kGeneralized,  // p = A(q) u, the paper's
  kCentroidal,   // whole-body angular and linear momentum about the centre of mass
};
[[nodiscard]] const char* MomentumKindName(MomentumKind kind);

struct SegmentOptions {
  double threshold = 0.75;          // ΔP_th: paper, Sec. III-B
  double threshold_quantile = -1;   // in (0, 1): use this quantile of ΔP as the threshold instead
  double analysis_rate = 100.0;     // Hz: paper, Fig. 3
  double min_duration = 0.8;        // s: the reference implementation's cooldown between boundaries
  MomentumKind momentum = MomentumKind::kGeneralized;

  bool IsValid(std::string* error) const;
  nlohmann::json ToJson() const;
};

// What syn-segment finds is what its file holds.
using Segmentation = SegmentsData;

// Throws DataError if the motion does not belong to the model (SHA-256 differs).
[[nodiscard]] Segmentation SegmentMotion(const MotionData& motion, const Model& model, const SegmentOptions& options);

}  // namespace syn
