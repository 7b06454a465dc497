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

namespace syn {

struct SegmentOptions {
  double threshold = 0.75;          // ΔP_th: paper, Sec. III-B
  double threshold_quantile = -1;   // in (0, 1): use this quantile of ΔP as the threshold instead
  double analysis_rate = 100.0;     // Hz: paper, Fig. 3
  double min_duration = 0.8;        // s: the reference implementation's cooldown between boundaries
  std::string momentum = "generalized";  // or "centroidal" (whole-body linear + angular momentum about the COM)

  bool IsValid(std::string* error) const;
  nlohmann::json ToJson() const;
};

struct Segmentation {
  std::vector<double> analysis_time;     // [Ta] s
  std::vector<double> delta_p;           // [Ta], ΔP at each analysis sample (0 at the first)
  std::vector<int64_t> boundaries;       // [S+1] frame indices into the motion: 0, ..., T
  std::vector<std::string> reasons;      // [S+1] why each boundary was placed
  double threshold_used = 0.0;
};

// Throws DataError if the motion does not belong to the model (SHA-256 differs).
[[nodiscard]] Segmentation SegmentMotion(const MotionData& motion, const Model& model, const SegmentOptions& options);

}  // namespace syn
