#include "stages/compose/composer.h"

#include <algorithm>
#include <cmath>
#include <sstream>

#include "common/cubic_spline.h"
#include "common/error.h"
#include "common/motion_from_trajectory.h"
#include "common/motion_integration.h"
#include "common/row_major.h"

namespace syn {

struct Composer::Piece {
  int step = 0;
  double start = 0, duration = 0, tempo = 1;
  double blend_out = 0;  // s, the cross-fade window into the next piece (clamped to both pieces)
  Interpolation interpolation = Interpolation::kMinimumJerk;
  std::vector<double> knots;  // normalized sample instants of the segment, 0 .. 1
  CubicSpline profiles;       // scores U(s), [knots, k]
  std::vector<double> keyframe_at;
  Eigen::MatrixXd keyframe_coefficients;  // [keyframes, k], absolute a_i
};

namespace {

// Absolute coefficients of a keyframe, checked against the synergy's k.
Eigen::VectorXd KeyframeCoefficients(const CoefficientKeyframe& keyframe, const Eigen::VectorXd& sigma,
                                     const std::string& script, const std::string& synergy) {
  const std::vector<double>& given = keyframe.coefficients.empty() ? keyframe.gains : keyframe.coefficients;
  if (static_cast<Eigen::Index>(given.size()) != sigma.size()) {
    throw DataError(Location::AtLine(script, keyframe.line),
                    std::string(keyframe.coefficients.empty() ? "gain" : "coefficients") + " has " +
                        std::to_string(given.size()) + " values but synergy '" + synergy + "' has " +
                        std::to_string(sigma.size()) + " components");
  }
  Eigen::VectorXd a(sigma.size());
  for (Eigen::Index i = 0; i < a.size(); ++i) {
    a[i] = keyframe.coefficients.empty() ? given[static_cast<size_t>(i)] * sigma[i] : given[static_cast<size_t>(i)];
  }
  return a;
}

}  // namespace

Composer::Composer(const ComposeScript& script, const LibraryReader& library, const Model& model, Eigen::VectorXd start_q)
    : script_(script), model_(model), start_q_(std::move(start_q)) {
  if (library.velocityNames() != model.velocityNames()) {
    throw DataError(Location::InFile(library.path()),
                    "the library's velocities are not those of " + model.name() +
                        " (a library of another robot, or built with --velocities joints)");
  }
  if (start_q_.size() != model.nq()) {
    throw DataError(Location::AtLine(script.file, script.start_line), "the start pose does not fit " + model.name());
  }
  double clock = 0;
  for (size_t s = 0; s < script.steps.size(); ++s) {
    const ComposeStep& step = script.steps[s];
    if (!library.has(step.synergy)) {
      try {
        (void)library.read(step.synergy);
      } catch (const DataError& error) {
        throw DataError(Location::AtLine(script.file, step.line), error.what());
      }
    }
    synergies_.push_back(library.read(step.synergy));
    const LibrarySynergy& synergy = synergies_.back();
    const TrialSynergies::Segment& segment = synergy.segment;
    const double own_duration = segment.times.back() - segment.times.front();
    if (segment.times.size() < 2 || !(own_duration > 0)) {
      throw DataError(Location::AtLine(script.file, step.line), "synergy '" + step.synergy + "' has fewer than 2 samples");
    }
    Piece piece;
    piece.step = static_cast<int>(s);
    piece.duration = step.duration.value_or(own_duration);
    piece.tempo = own_duration / piece.duration;
    piece.interpolation = step.interpolation;
    for (double t : segment.times) piece.knots.push_back((t - segment.times.front()) / own_duration);
    piece.profiles = CubicSpline(piece.knots, RowMajorValues(segment.synergies.scores), segment.synergies.scores.cols());
    const Eigen::VectorXd& sigma = segment.synergies.singular_values;
    piece.keyframe_coefficients.resize(std::max<Eigen::Index>(1, static_cast<Eigen::Index>(step.keyframes.size())), sigma.size());
    if (step.keyframes.empty()) {
      piece.keyframe_at = {0.0};
      piece.keyframe_coefficients.row(0) = sigma.transpose();
    }
    for (size_t k = 0; k < step.keyframes.size(); ++k) {
      piece.keyframe_at.push_back(step.keyframes[k].at);
      piece.keyframe_coefficients.row(static_cast<Eigen::Index>(k)) =
          KeyframeCoefficients(step.keyframes[k], sigma, script.file, step.synergy).transpose();
    }
    for (int r = 0; r < step.repetitions; ++r) {
      piece.start = clock;
      piece.blend_out = step.interpolation == Interpolation::kStep ? 0.0 : step.blend;
      pieces_.push_back(piece);
      clock += piece.duration;
    }
  }
  // Cross-fade windows may not reach past the middle of either neighbour.
  for (size_t p = 0; p < pieces_.size(); ++p) {
    pieces_[p].blend_out = p + 1 < pieces_.size()
                               ? std::min({pieces_[p].blend_out, pieces_[p].duration, pieces_[p + 1].duration})
                               : 0.0;
  }
  blend_scratch_.resize(model.nu());
  for (size_t p = 0; p < pieces_.size(); ++p) {
    for (size_t j = p == 0 ? 0 : 1; j < pieces_[p].knots.size(); ++j) {
      times_.push_back(pieces_[p].start + pieces_[p].knots[j] * pieces_[p].duration);
      sample_piece_.push_back(static_cast<int>(p));
    }
  }
}

Composer::~Composer() = default;

std::vector<double> Composer::boundaries() const {
  std::vector<double> result;
  for (size_t p = 1; p < pieces_.size(); ++p) result.push_back(pieces_[p].start);
  return result;
}

void Composer::pieceVelocity(const Piece& piece, double t, const StepScales& scales, Eigen::Ref<Eigen::VectorXd> out) const {
  const SegmentSynergies& pca = synergies_[static_cast<size_t>(piece.step)].segment.synergies;
  const Eigen::Index k = pca.components.rows();
  const double s = (t - piece.start) / piece.duration;
  // Time profiles, extended linearly past the segment's ends (the natural spline's curvature is zero there).
  double profile[64], slope[64];
  if (k > 64) throw std::length_error("more than 64 synergies per segment");
  const double clamped = std::clamp(s, 0.0, 1.0);
  piece.profiles.evaluate(clamped, profile, slope);
  for (Eigen::Index i = 0; i < k; ++i) profile[i] += slope[i] * (s - clamped);
  // Coefficients between keyframes, held before the first and after the last.
  const std::vector<double>& at = piece.keyframe_at;
  size_t next = static_cast<size_t>(std::upper_bound(at.begin(), at.end(), s) - at.begin());
  out = pca.mean;
  for (Eigen::Index i = 0; i < k; ++i) {
    double a;
    if (next == 0) {
      a = piece.keyframe_coefficients(0, i);
    } else if (next == at.size()) {
      a = piece.keyframe_coefficients(static_cast<Eigen::Index>(at.size() - 1), i);
    } else {
      const double x = (s - at[next - 1]) / (at[next] - at[next - 1]);
      const double w = BlendWeight(piece.interpolation, x);
      a = (1 - w) * piece.keyframe_coefficients(static_cast<Eigen::Index>(next - 1), i) +
          w * piece.keyframe_coefficients(static_cast<Eigen::Index>(next), i);
    }
    out += (a * profile[i]) * pca.components.row(i).transpose();
  }
  out = piece.tempo * out.cwiseProduct(scales.row(piece.step).transpose());
}

void Composer::velocityAt(double t, const StepScales& step_scales, Eigen::Ref<Eigen::VectorXd> out) const {
  // The piece whose span holds t; a boundary instant belongs to the earlier piece.
  size_t p = 0;
  while (p + 1 < pieces_.size() && t > pieces_[p].start + pieces_[p].duration) ++p;
  const Piece& piece = pieces_[p];
  pieceVelocity(piece, t, step_scales, out);
  Eigen::VectorXd& other = blend_scratch_;
  const double end = piece.start + piece.duration;
  if (p + 1 < pieces_.size() && piece.blend_out > 0 && t > end - 0.5 * piece.blend_out) {
    const Piece& next = pieces_[p + 1];
    const double w = BlendWeight(piece.interpolation, (t - (end - 0.5 * piece.blend_out)) / piece.blend_out);
    pieceVelocity(next, t, step_scales, other);
    out = (1 - w) * out + w * other;
  } else if (p > 0 && pieces_[p - 1].blend_out > 0 && t < piece.start + 0.5 * pieces_[p - 1].blend_out) {
    const Piece& before = pieces_[p - 1];
    const double w = BlendWeight(before.interpolation, (t - (piece.start - 0.5 * before.blend_out)) / before.blend_out);
    pieceVelocity(before, t, step_scales, other);
    out = (1 - w) * other + w * out;
  }
}

void Composer::integrate(const StepScales& step_scales, Eigen::MatrixXd& q, Eigen::MatrixXd& u) const {
  const Eigen::Index frames = static_cast<Eigen::Index>(times_.size());
  Eigen::MatrixXd heading(frames, model_.nu());
  Eigen::VectorXd row(model_.nu());
  for (Eigen::Index i = 0; i < frames; ++i) {
    velocityAt(times_[static_cast<size_t>(i)], step_scales, row);
    heading.row(i) = row.transpose();
  }
  IntegrateVelocities(model_.hasFreeBase(), start_q_,
                      Eigen::Map<const Eigen::VectorXd>(times_.data(), frames), heading,
                      model_.hasFreeBase() ? BaseVelocityFrame::kHeading : BaseVelocityFrame::kGround, q, u);
}

namespace {

// Feasible values of c for L ≤ a + c b ≤ U, intersected into [low, high].
void Restrict(double a, double b, double lower, double upper, double& low, double& high) {
  if (std::abs(b) < 1e-15) {
    if (a < lower || a > upper) high = -1;  // violated whatever the scale: infeasible
    return;
  }
  double c1 = (lower - a) / b, c2 = (upper - a) / b;
  if (c1 > c2) std::swap(c1, c2);
  low = std::max(low, c1);
  high = std::min(high, c2);
}

}  // namespace

ComposedMotion Composer::compose() const {
  ComposedMotion result;
  const Eigen::Index steps = static_cast<Eigen::Index>(script_.steps.size()), nu = model_.nu();
  StepScales scales = StepScales::Ones(steps, nu);
  constexpr double kTolerance = 1e-9;
  Eigen::MatrixXd q_without, u_without, q_with, u_with;
  // Steps are decided in order. While step s is decided, later steps' joint motion is held at zero, so the
  // pose step s leaves behind must itself stay within limits; the next step then always starts feasible.
  auto hold_joints = [&](StepScales& trial, Eigen::Index from) {
    for (Eigen::Index later = from; later < steps; ++later) {
      for (const ModelJoint& joint : model_.joints()) {
        if (joint.u_index >= 0 && joint.type != "free") trial(later, joint.u_index) = 0;
      }
      if (script_.scale_whole_step) trial.row(later).setZero();
    }
  };
  for (Eigen::Index s = 0; s < steps; ++s) {
    // A joint coordinate is linear in the step's scale c (q̇ = u for joints): q = q_without + c (q_with − q_without),
    // so the largest c that keeps every affected sample within range and velocity limits is exact.
    StepScales trial = scales;
    hold_joints(trial, s);
    integrate(trial, q_without, u_without);
    trial.row(s) = scales.row(s);
    hold_joints(trial, s + 1);
    integrate(trial, q_with, u_with);
    // Step s acts from its first sample, or from the cross-fade window before it.
    double first_time = 0;
    for (size_t p = 0; p < pieces_.size(); ++p) {
      if (pieces_[p].step != s) continue;
      first_time = pieces_[p].start - (p > 0 ? 0.5 * pieces_[p - 1].blend_out : 0.0);
      break;
    }
    double step_scale = 1;
    std::string limiting;
    for (const ModelJoint& joint : model_.joints()) {
      if (joint.q_index < 0 || joint.type == "free") continue;
      const double lower = model_.qLower()[joint.q_index] - kTolerance, upper = model_.qUpper()[joint.q_index] + kTolerance;
      const double speed = model_.uLimit()[joint.u_index] + kTolerance;
      double low = 0, high = 1;
      std::ostringstream reason;
      reason.precision(4);
      for (size_t i = 0; i < times_.size(); ++i) {
        if (times_[i] < first_time - 1e-12) continue;
        const Eigen::Index row = static_cast<Eigen::Index>(i);
        const double qa = q_without(row, joint.q_index), qb = q_with(row, joint.q_index) - qa;
        const double ua = u_without(row, joint.u_index), ub = u_with(row, joint.u_index) - ua;
        const double before = high;
        Restrict(qa, qb, lower, upper, low, high);
        if (high < before && reason.tellp() == 0) {
          reason << "reaches " << qa + qb << " rad at t = " << times_[i] << " s, outside [" << lower + kTolerance << ", "
                 << upper - kTolerance << "]";
        }
        const double before_speed = high;
        Restrict(ua, ub, -speed, speed, low, high);
        if (high < before_speed && reason.tellp() == 0) {
          reason << "moves at " << std::abs(ua + ub) << " rad/s at t = " << times_[i] << " s, above its limit "
                 << speed - kTolerance;
        }
      }
      const double c = high >= low ? std::clamp(high, 0.0, 1.0) : 0.0;
      if (c >= 1) continue;
      std::ostringstream warning;
      warning.precision(4);
      warning << script_.file << ":" << script_.steps[static_cast<size_t>(s)].line << ": step " << s + 1 << " ("
              << script_.steps[static_cast<size_t>(s)].synergy << "): joint '" << joint.name << "' at full scale "
              << reason.str() << (high < low ? " (and cannot be kept within them at any scale: frozen)" : "");
      if (script_.scale_whole_step) {
        if (c < step_scale) {
          step_scale = c;
          limiting = warning.str();
        }
      } else {
        scales(s, joint.u_index) *= c;
        warning << "; its motion in this step scaled by " << c;
        result.warnings.push_back(warning.str());
      }
    }
    if (script_.scale_whole_step && step_scale < 1) {
      scales.row(s) *= step_scale;
      std::ostringstream note;
      note.precision(4);
      note << "; the whole step scaled by " << step_scale;
      result.warnings.push_back(limiting + note.str());
    }
  }
  Eigen::MatrixXd q, u;
  integrate(scales, q, u);
  result.step_scales = scales;
  for (const Piece& piece : pieces_) {
    if (result.step_start_times.size() == static_cast<size_t>(piece.step)) result.step_start_times.push_back(piece.start);
  }

  result.motion = MotionFromTrajectory(model_, times_, q, u);
  return result;
}

Eigen::VectorXd Composer::StartPose(const ComposeScript& script, const LibraryReader& library) {
  auto from_synergy = [&](const std::string& name, int line) {
    if (!library.has(name)) {
      try {
        (void)library.read(name);
      } catch (const DataError& error) {
        throw DataError(Location::AtLine(script.file, line), error.what());
      }
    }
    const std::vector<double> q0 = library.read(name).segment.q0;
    return Eigen::VectorXd(Eigen::Map<const Eigen::VectorXd>(q0.data(), static_cast<Eigen::Index>(q0.size())));
  };
  if (!script.start_synergy.empty()) return from_synergy(script.start_synergy, script.start_line);
  if (script.start_motion.empty()) return from_synergy(script.steps.front().synergy, script.steps.front().line);
  const MotionData motion = ReadMotionFile(script.start_motion);
  if (motion.frames() < 2 || script.start_time < motion.time_s.front() || script.start_time > motion.time_s.back()) {
    throw DataError(Location::AtLine(script.file, script.start_line),
                    "start time " + std::to_string(script.start_time) + " s is outside " + script.start_motion);
  }
  const bool free_base = motion.nq() == motion.nu() + 1;
  std::vector<double> q = motion.q;
  if (free_base) MakeBaseQuaternionsContinuous(q, motion.nq());
  Eigen::VectorXd pose(motion.nq());
  CubicSpline(motion.time_s, q, motion.nq()).evaluate(script.start_time, pose.data(), nullptr);
  if (free_base) pose.head<4>().normalize();
  return pose;
}

}  // namespace syn
