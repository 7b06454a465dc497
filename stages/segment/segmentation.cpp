#include "stages/segment/segmentation.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/configuration_space.h"
#include "common/error.h"

namespace syn {

const char* MomentumKindName(MomentumKind kind) {
  return kind == MomentumKind::kCentroidal ? "centroidal" : "generalized";
}

bool SegmentOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& message) {
    if (error) *error = message;
    return false;
  };
  if (!(threshold > 0)) return fail("--threshold must be positive");
  if (threshold_quantile != -1 && !(threshold_quantile > 0 && threshold_quantile < 1)) {
    return fail("--threshold-quantile must lie in (0, 1)");
  }
  if (!(analysis_rate > 0)) return fail("--analysis-rate must be positive");
  if (!(min_duration >= 0)) return fail("--min-duration must be >= 0");
  return true;
}

nlohmann::json SegmentOptions::ToJson() const {
  return {{"threshold", threshold}, {"threshold_quantile", threshold_quantile}, {"analysis_rate", analysis_rate},
          {"min_duration", min_duration}, {"momentum", MomentumKindName(momentum)}};
}

Segmentation SegmentMotion(const MotionData& motion, const Model& model, const SegmentOptions& options) {
  CheckMotionMatchesModel(motion, model);
  const int64_t frames = motion.frames();
  const int64_t nq = motion.nq(), nu = motion.nu();
  Segmentation result;
  result.analysis_rate = options.analysis_rate;
  if (frames == 0) return result;

  // The state at each analysis instant (linear between frames; a free base's orientation by normalised lerp), then its momentum: one Simbody A·u per analysis sample, wherever the motion's frames fall.
  const int width = options.momentum == MomentumKind::kCentroidal ? 6 : static_cast<int>(nu);
  const ConfigurationShape shape = ConfigurationShape::Of(model.hasFreeBase(), static_cast<int>(nq));
  Workspace workspace(model);
  Eigen::VectorXd q(nq), u(nu), p(width), p_before(width);
  const double start = motion.time_s.front(), end = motion.time_s.back();
  const int64_t samples = static_cast<int64_t>(std::floor((end - start) * options.analysis_rate + 1e-9)) + 1;
  result.analysis_time.resize(static_cast<size_t>(samples));
  result.delta_p.assign(static_cast<size_t>(samples), 0.0);
  size_t segment = 0;
  for (int64_t i = 0; i < samples; ++i) {
    const double time = start + static_cast<double>(i) / options.analysis_rate;
    result.analysis_time[static_cast<size_t>(i)] = time;
    while (segment + 2 < static_cast<size_t>(frames) && motion.time_s[segment + 1] <= time) ++segment;
    const size_t next = std::min(segment + 1, static_cast<size_t>(frames - 1));
    const double span = motion.time_s[next] - motion.time_s[segment];
    const double fraction = span > 0 ? std::clamp((time - motion.time_s[segment]) / span, 0.0, 1.0) : 0.0;
    const double* q0 = &motion.q[segment * static_cast<size_t>(nq)];
    const double* q1 = &motion.q[next * static_cast<size_t>(nq)];
    const double* u0 = &motion.u[segment * static_cast<size_t>(nu)];
    const double* u1 = &motion.u[next * static_cast<size_t>(nu)];
    // Unnormalised: setQ normalises the quaternion, and normalising once keeps ΔP the same to the last bit
    // as before configuration-space maths moved to common/ (the demo release's SHA-256 with it).
    InterpolateUnnormalized(shape, q0, q1, fraction, q.data());
    for (int64_t k = 0; k < nu; ++k) u[k] = (1 - fraction) * u0[k] + fraction * u1[k];
    workspace.setQ(q);  // normalises the quaternion
    if (options.momentum == MomentumKind::kCentroidal) {
      workspace.setU(u);
      p = workspace.calcCentroidalMomentum();
    } else {
      workspace.calcMassTimes(u, p);  // A(q) u needs positions only: no velocity-stage realisation
    }
    if (i > 0) result.delta_p[static_cast<size_t>(i)] = (p - p_before).norm();
    p_before.swap(p);
  }

  // Threshold and boundaries.
  result.threshold_used = options.threshold;
  if (options.threshold_quantile > 0 && samples > 1) {
    std::vector<double> sorted(result.delta_p.begin() + 1, result.delta_p.end());
    std::sort(sorted.begin(), sorted.end());
    result.threshold_used = sorted[static_cast<size_t>(options.threshold_quantile * static_cast<double>(sorted.size() - 1))];
  }
  const auto nearest_frame = [&](double time) {
    const auto it = std::lower_bound(motion.time_s.begin(), motion.time_s.end(), time - 1e-12);
    int64_t frame = it - motion.time_s.begin();
    if (frame > 0 && (frame >= frames || std::abs(motion.time_s[static_cast<size_t>(frame - 1)] - time) <
                                             std::abs(motion.time_s[static_cast<size_t>(frame)] - time))) {
      --frame;
    }
    return std::min(frame, frames - 1);
  };
  result.boundaries.push_back(0);
  result.reasons.push_back("start of the motion");
  double last = start;
  for (int64_t i = 1; i < samples; ++i) {
    const double value = result.delta_p[static_cast<size_t>(i)];
    const double time = result.analysis_time[static_cast<size_t>(i)];
    if (value <= result.threshold_used || time - last < options.min_duration) continue;
    const int64_t frame = nearest_frame(time);
    if (frame <= result.boundaries.back() || frame >= frames - 1) continue;
    std::ostringstream reason;
    reason << "dP = " << value << " > " << result.threshold_used << " at " << time << " s, " << time - last
           << " s after the previous boundary";
    result.boundaries.push_back(frame);
    result.reasons.push_back(reason.str());
    last = time;
  }
  result.boundaries.push_back(frames);
  result.reasons.push_back("end of the motion");
  return result;
}

}  // namespace syn
