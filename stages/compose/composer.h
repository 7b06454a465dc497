// syn-compose: a motion from a script of library synergies (the paper's
// Motion Editor). Each step plays one segment's synergies,
//
//   û(t) = c · (D0 / D) · (mean + Σ_i a_i(s) U_i(s) V_i),   s = (t − t_step) / D ∈ [0, 1]
//
// with the segment's own time profiles U_i (cubic splines over its samples,
// extended linearly past its ends — C2, because the splines are natural),
// coefficients a_i(s) interpolated between keyframes, the tempo D0 / D that
// keeps the step's displacement when its duration D differs from the
// segment's D0, and scales c ≤ 1 that the limits may impose. Between
// consecutive steps (and repetitions) the two profiles cross-fade over the
// step's `blend` window centred on the boundary with the step's
// interpolation weight, so the velocity is discontinuous for `step`, C0 for
// `linear`, C1 for `cubic` and C2 for `minimum-jerk`.
//
// Each step keeps its segment's samples (re-timed by the tempo), so the
// composition of one synergy at its own duration lands on the very instants
// of its reconstruction, and a tempo change moves samples rather than
// resampling them. Poses come from integrating û from the start pose
// (quaternion-aware; base velocities in the heading frame, as the synergies
// store them): each step continues from where the previous one ended.
//
// Limits: a joint that would leave its position range or exceed its velocity
// limit during a step has its motion in that step scaled down by the largest
// factor that keeps it within (exact: a joint coordinate is linear in the
// factor), with a warning naming the step and the joint; nothing is clipped.
// With `limit_scaling = "step"` the whole step is scaled by the smallest such
// factor instead, which keeps the synergy's direction at the cost of the
// other joints' amplitude.
#pragma once

#include <string>
#include <vector>

#include "common/model.h"
#include "common/motion_file.h"
#include "stages/compose/compose_script.h"
#include "common/library_file.h"

namespace syn {

// Per script step and velocity: the factor the limits imposed on the step's velocity (1: none).
using StepScales = Eigen::MatrixXd;  // [steps, nu]

struct ComposedMotion {
  MotionData motion;
  StepScales step_scales;
  std::vector<double> step_start_times;  // s, per script step (first repetition)
  std::vector<std::string> warnings;     // one per scaled step, naming the step and the joint
};

class Composer {
 public:
  // Resolves every synergy of the script in the library; a missing one is a DataError at script:line.
  Composer(const ComposeScript& script, const LibraryReader& library, const Model& model, Eigen::VectorXd start_q);
  ~Composer();

  // The composed velocity (heading-frame base velocities) at time t, with per-step scales.
  void velocityAt(double t, const StepScales& step_scales, Eigen::Ref<Eigen::VectorXd> out) const;
  // Boundary times between consecutive pieces (steps and repetitions).
  std::vector<double> boundaries() const;

  // The start pose for a script: its start synergy's q0, a motion file's pose at a time (cubic, quaternion
  // renormalised), or the first step's q0.
  [[nodiscard]] static Eigen::VectorXd StartPose(const ComposeScript& script, const LibraryReader& library);

  // Samples, integrates, enforces joint position and velocity limits by scaling down, and runs
  // inverse dynamics.
  [[nodiscard]] ComposedMotion compose() const;

 private:
  struct Piece;
  void pieceVelocity(const Piece& piece, double t, const StepScales& scales, Eigen::Ref<Eigen::VectorXd> out) const;
  void integrate(const StepScales& step_scales, Eigen::MatrixXd& q, Eigen::MatrixXd& u) const;

  const ComposeScript& script_;
  const Model& model_;
  Eigen::VectorXd start_q_;
  std::vector<LibrarySynergy> synergies_;  // per script step
  std::vector<Piece> pieces_;
  std::vector<double> times_;              // output samples
  std::vector<int> sample_piece_;          // owning piece per sample
  mutable Eigen::VectorXd blend_scratch_;
};

}  // namespace syn
