// Per-trial quality figures of a release, so a user can filter trials: read from the trial's motion.h5
// (landmark errors, contact flags and the stance/penetration figures syn-retarget stores) and metrics.json
// (syn-evaluate's foot sliding). Nothing here recomputes a stage's figure: absent data reads as NaN, which
// the release prints as "n/a".
#pragma once

#include <map>
#include <string>
#include <vector>

namespace syn {

struct TrialQuality {
  int64_t frames = 0;
  double duration_s = 0;  // time[T-1] - time[0], as syn-evaluate's motion.duration_s
  double rate_hz = 0;     // (frames - 1) / duration_s
  // Landmark tracking errors over every frame with a target, per priority level of the robot map
  // (P1 = priority 1, P2 = priority 2): median and 95th percentile, nearest rank round(p·(n-1)) — the
  // figures syn-retarget prints. Position in mm, angle in degrees; NaN where the level has no such task.
  double p1_position_median_mm = 0, p1_position_p95_mm = 0, p1_angle_median_deg = 0, p1_angle_p95_deg = 0;
  double p2_position_median_mm = 0, p2_position_p95_mm = 0, p2_angle_median_deg = 0, p2_angle_p95_deg = 0;
  // syn-retarget's contact figures (root attributes of motion.h5), NaN when the file has none.
  double stance_drift_median_mm = 0, stance_drift_p95_mm = 0, deepest_penetration_mm = 0, penetration_frames_ratio = 0;
  std::vector<std::string> contact_feet;  // empty when motion.h5 has no contact flags
  double foot_sliding_ratio = 0;          // syn-evaluate, metrics.json trial.foot_sliding_ratio; NaN if absent
};


// `priority_of_landmark`: landmark name -> priority level (from the robot map); landmarks it does not
// name count as priority 1.
[[nodiscard]] TrialQuality ReadTrialQuality(const std::string& motion_path, const std::string& metrics_path,
                                            const std::map<std::string, int>& priority_of_landmark);

// The contact flags of motion.h5 as CSV: header "time,<foot>,...", one row per frame, 1 = planted; ""
// when the file has none.
[[nodiscard]] std::string ContactFlagsCsv(const std::string& motion_path);

// A figure for a table: fixed decimals, "n/a" for NaN.
[[nodiscard]] std::string FigureText(double value, int decimals);

}  // namespace syn
