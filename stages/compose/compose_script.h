// Compose scripts (manifests/scripts/*.toml): a SynSculptor motion as a
// versionable text file. See manifests/scripts/README.md for the format.
//
//   model = "datasets/robots/unitree_g1/g1_29dof.urdf"
//   limit_scaling = "joint"                    # or "step" (stages/compose/composer.h, Limits)
//   start = { synergy = "salsa/60_10/0" }      # or { motion = "x.motion.h5", time = 1.5 }
//   [[step]]
//   synergy = "salsa/60_10/2"                  # STYLE/TRIAL/SEGMENT in the library
//   gain = [1.2, 1.0, 0.8]                     # a_i = gain_i σ_i  (or coefficients = [a_1, ...])
//   duration = 0.9                             # s; a tempo change: the displacement is kept
//   repetitions = 2
//   interpolation = "minimum-jerk"             # step | linear | cubic | minimum-jerk
//   blend = 0.2                                # s of velocity blend into the next step
//   [[step.keyframe]]                          # coefficients over the step's normalized time
//   at = 0.5
//   gain = [1.5, 1.0, 1.0]
#pragma once

#include <optional>
#include <string>
#include <vector>

namespace syn {

enum class Interpolation { kStep, kLinear, kCubic, kMinimumJerk };

[[nodiscard]] Interpolation InterpolationFromName(const std::string& name);  // throws std::invalid_argument
[[nodiscard]] const char* InterpolationName(Interpolation interpolation);
// The blend weight w(x) on [0, 1]: 0 → 1 with zero slope (cubic) and zero slope and curvature
// (minimum-jerk) at both ends; `step` jumps at x = 1.
[[nodiscard]] double BlendWeight(Interpolation interpolation, double x);

struct CoefficientKeyframe {
  double at = 0;  // normalized step time in [0, 1]
  // Either absolute coefficients or gains on σ_i (one of the two is filled).
  std::vector<double> coefficients, gains;
  int line = 0;
};

struct ComposeStep {
  std::string synergy;  // STYLE/TRIAL/SEGMENT
  std::vector<CoefficientKeyframe> keyframes;  // sorted by `at`; empty: a_i = σ_i
  std::optional<double> duration;              // s; default the segment's own
  int repetitions = 1;
  Interpolation interpolation = Interpolation::kMinimumJerk;
  double blend = 0.2;  // s
  int line = 0;
};

struct ComposeScript {
  std::string file;
  std::string model;  // URDF path
  std::string floating_base = "auto";
  bool scale_whole_step = false;  // limit_scaling = "step" (default "joint")
  // Start pose: a library synergy's q0, or a motion file at a time. Default: the first step's q0.
  std::string start_synergy, start_motion;
  double start_time = 0;
  int start_line = 0;
  std::vector<ComposeStep> steps;
};

// Throws DataError at script:line.
[[nodiscard]] ComposeScript LoadComposeScript(const std::string& path);
// The same from a script's text (the studio's POST body), errors located at file_name:line.
[[nodiscard]] ComposeScript ParseComposeScript(const std::string& toml_text, const std::string& file_name);

}  // namespace syn
