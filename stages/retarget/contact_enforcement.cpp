#include "stages/retarget/contact_enforcement.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <utility>

#include <Eigen/Geometry>
#include <Eigen/SVD>

#include "common/configuration_space.h"
#include "common/error.h"
#include "common/percentile.h"
#include "common/tree_kinematics.h"
#include "stages/retarget/base_mover.h"
#include "stages/retarget/branch_joints.h"
#include "stages/retarget/leg_chain.h"

namespace syn {
namespace {

// A sole in its link's frame: its points, their centre, the plane's normal pointing into the foot, and
// the foot's forward direction in that plane.
struct SoleGeometry {
  std::vector<Eigen::Vector3d> points;
  Eigen::Vector3d centre = Eigen::Vector3d::Zero();
  Eigen::Vector3d normal = Eigen::Vector3d::UnitZ();
  Eigen::Vector3d forward = Eigen::Vector3d::UnitX();
};

SoleGeometry SoleOf(const RobotFoot& foot) {
  SoleGeometry sole;
  for (const auto& point : foot.sole_points) sole.points.emplace_back(point[0], point[1], point[2]);
  if (sole.points.empty()) sole.points.push_back(Eigen::Vector3d::Zero());
  for (const Eigen::Vector3d& point : sole.points) sole.centre += point / static_cast<double>(sole.points.size());
  if (sole.points.size() >= 3) {
    Eigen::MatrixXd centred(static_cast<Eigen::Index>(sole.points.size()), 3);
    for (size_t i = 0; i < sole.points.size(); ++i) centred.row(static_cast<Eigen::Index>(i)) = (sole.points[i] - sole.centre).transpose();
    const Eigen::JacobiSVD<Eigen::MatrixXd> svd(centred, Eigen::ComputeFullV);
    // A plane needs two spread directions; collinear points (a line of contact) keep the link's z.
    if (svd.singularValues()[1] > 1e-3 * svd.singularValues()[0]) sole.normal = svd.matrixV().col(2);
  }
  if (sole.normal.dot(-sole.centre) < 0) sole.normal = -sole.normal;
  sole.forward = Eigen::Vector3d::UnitX() - Eigen::Vector3d::UnitX().dot(sole.normal) * sole.normal;
  if (sole.forward.norm() < 1e-6) sole.forward = sole.normal.cross(Eigen::Vector3d::UnitY());
  sole.forward.normalize();
  return sole;
}

double Yaw(const Eigen::Matrix3d& rotation, const SoleGeometry& sole) {
  const Eigen::Vector3d forward = rotation * sole.forward;
  return std::atan2(forward.y(), forward.x());
}

// The link pose that lays the sole flat on z = 0 with its centre at (x, y) and the given yaw.
Eigen::Isometry3d PlantedPose(const SoleGeometry& sole, double x, double y, double yaw) {
  const Eigen::Matrix3d level = Eigen::Quaterniond::FromTwoVectors(sole.normal, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  Eigen::Isometry3d pose = Eigen::Isometry3d::Identity();
  pose.linear() = Eigen::AngleAxisd(yaw - Yaw(level, sole), Eigen::Vector3d::UnitZ()).toRotationMatrix() * level;
  pose.translation() = Eigen::Vector3d(x, y, 0.0) - pose.linear() * sole.centre;
  return pose;
}

// m: a planted sole centre this far from its plant (horizontally) is counted out of reach.
constexpr double kOffPlant = 0.005;

double LowestPoint(const SoleGeometry& sole, const Eigen::Isometry3d& pose) {
  double lowest = std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& point : sole.points) lowest = std::min(lowest, (pose * point).z());
  return lowest;
}

// How far `pose` pitches from `target` about the sole's lateral axis (> 0: toes down), rad.
double PitchFrom(const SoleGeometry& sole, const Eigen::Isometry3d& target, const Eigen::Isometry3d& pose) {
  const Eigen::Vector3d lateral = target.linear() * sole.normal.cross(sole.forward);
  const Eigen::AngleAxisd between(pose.linear() * target.linear().transpose());
  return (between.axis() * between.angle()).dot(lateral);
}

// `target` rolled by `pitch` about the sole edge it pitches onto (the toe line for toes down, the heel line
// for heel down): that edge stays put and the other end lifts.
Eigen::Isometry3d RollBy(const SoleGeometry& sole, const Eigen::Isometry3d& target, double pitch) {
  const Eigen::Vector3d lateral = target.linear() * sole.normal.cross(sole.forward);
  double extreme = pitch > 0 ? -std::numeric_limits<double>::infinity() : std::numeric_limits<double>::infinity();
  for (const Eigen::Vector3d& point : sole.points) {
    const double along = point.dot(sole.forward);
    extreme = pitch > 0 ? std::max(extreme, along) : std::min(extreme, along);
  }
  Eigen::Vector3d edge = Eigen::Vector3d::Zero();
  int on_edge = 0;
  for (const Eigen::Vector3d& point : sole.points) {
    if (std::abs(point.dot(sole.forward) - extreme) < 1e-3) edge += point, ++on_edge;
  }
  const Eigen::Vector3d pivot = target * (edge / std::max(on_edge, 1));
  const Eigen::Matrix3d roll = Eigen::AngleAxisd(pitch, lateral).toRotationMatrix();
  Eigen::Isometry3d rolled = target;
  rolled.linear() = roll * target.linear();
  rolled.translation() = pivot + roll * (target.translation() - pivot);
  return rolled;
}

// Where the leg's joint limits leave the reached foot pitched against its target (late in stance the body
// passes over the planted foot further than the ankle bends), the target is rolled about the sole edge
// the foot pitches onto by that pitch: the other end lifts instead of going through the floor, as a human
// foot rolls off its toes.
Eigen::Isometry3d RollAboutSoleEdge(const SoleGeometry& sole, const Eigen::Isometry3d& target, const Eigen::Isometry3d& reached) {
  return RollBy(sole, target, PitchFrom(sole, target, reached));
}

// A pose correction: translation and rotation vector, both in the ground frame.
struct Correction {
  Eigen::Vector3d translation = Eigen::Vector3d::Zero();
  Eigen::Vector3d rotation = Eigen::Vector3d::Zero();
};

Correction Between(const Eigen::Isometry3d& to, const Eigen::Isometry3d& from) {
  Correction correction;
  correction.translation = to.translation() - from.translation();
  const Eigen::AngleAxisd turn(to.linear() * from.linear().transpose());
  correction.rotation = turn.axis() * turn.angle();
  return correction;
}

Eigen::Isometry3d Apply(const Correction& correction, const Eigen::Isometry3d& pose) {
  Eigen::Isometry3d corrected = pose;
  corrected.translation() += correction.translation;
  const double angle = correction.rotation.norm();
  if (angle > 0) corrected.linear() = Eigen::AngleAxisd(angle, correction.rotation / angle).toRotationMatrix() * pose.linear();
  return corrected;
}

constexpr double kFloorTolerance = 0.5e-3;  // m below z = 0 that a reached sole point may be

// 1 at x = 0 down to 0 at x = 1, with zero slope at both ends.
double Ease(double x) { return x >= 1.0 ? 0.0 : x <= 0.0 ? 1.0 : 1.0 - x * x * (3.0 - 2.0 * x); }

// s: how long from a contact phase's ends a planted foot may roll with the source. The heel strike's loading
// response and the toe-off's pre-swing each last about a tenth of a walking gait cycle (Perry's gait phases),
// 0.1 s at a 1 s cycle; further in, the foot is flat (rolling through whole phases let CMU dance 05_02's
// feet pivot on their edges, its knees reaching their 20 rad/s limit and its foot skating 0.195 -> 0.23).
constexpr double kRollWindow = 0.1;

// Every frame's target for foot `foot`: its free pose, corrected towards its phases' planted poses and raised
// out of the floor. `corrected[t]` is set where either happened.
void FootTargets(const SoleGeometry& sole, const std::vector<Eigen::Isometry3d>& free, const std::vector<ContactPhase>& phases,
                 int foot, const std::vector<double>& time_s, double blend, double horizontal_blend, double max_roll,
                 std::vector<Eigen::Isometry3d>& target, std::vector<bool>& corrected) {
  const size_t frames = free.size();
  std::vector<Correction> correction(frames);
  std::vector<const ContactPhase*> own;
  for (const ContactPhase& phase : phases) {
    if (phase.foot == foot) own.push_back(&phase);
  }
  std::sort(own.begin(), own.end(), [](const ContactPhase* a, const ContactPhase* b) { return a->begin < b->begin; });
  std::vector<double> phase_pitch;
  for (const ContactPhase* phase : own) {
    double x = 0, y = 0, sine = 0, cosine = 0;
    for (int64_t t = phase->begin; t < phase->end; ++t) {
      const Eigen::Isometry3d& pose = free[static_cast<size_t>(t)];
      const Eigen::Vector3d centre = pose * sole.centre;
      x += centre.x(), y += centre.y();
      const double yaw = Yaw(pose.linear(), sole);
      sine += std::sin(yaw), cosine += std::cos(yaw);
    }
    const double n = static_cast<double>(phase->end - phase->begin);
    const Eigen::Isometry3d planted = PlantedPose(sole, x / n, y / n, std::atan2(sine, cosine));
    // Heel strike and toe-off (max_roll > 0): near the phase's ends, where the source foot pitches, the plant
    // rolls about the heel or toe edge with it (that edge stays put on the floor) instead of being held flat.
    // Held flat through a toe-off, the leg stretches while the source's knee bends, then flexes at once when
    // the foot lifts: CMU 02_01's knee reversed from -6 to +10 rad/s in one frame, 18.9 rad/s at most within 4
    // frames of a phase boundary (11.4 with G1's max_roll of 0.2 rad). The roll is the source's pitch from its
    // median over the phase, the foot's flat stance (a capture's foot landmark need not lie along the sole:
    // CMU's BVH foot pitches 18-37° toes down through 02_01's stances, and rolled by its whole pitch the robot
    // stood on its toes all stance), at most max_roll, fading to none kRollWindow from either end. The sole
    // centre moves with the roll, by (1 − cos max_roll) × its distance from the edge (G1: under 2 mm).
    phase_pitch.clear();
    for (int64_t t = phase->begin; t < phase->end && max_roll > 0; ++t) phase_pitch.push_back(PitchFrom(sole, planted, free[static_cast<size_t>(t)]));
    const double flat = phase_pitch.empty() ? 0.0 : NearestRankPercentile(phase_pitch, 0.5);
    const double first = time_s[static_cast<size_t>(phase->begin)], last = time_s[static_cast<size_t>(phase->end - 1)];
    for (int64_t t = phase->begin; t < phase->end; ++t) {
      const Eigen::Isometry3d& source = free[static_cast<size_t>(t)];
      const double now = time_s[static_cast<size_t>(t)];
      const double cap = max_roll * Ease(std::min(now - first, last - now) / kRollWindow);
      const Eigen::Isometry3d plant =
          cap > 0 ? RollBy(sole, planted, std::clamp(phase_pitch[static_cast<size_t>(t - phase->begin)] - flat, -cap, cap)) : planted;
      correction[static_cast<size_t>(t)] = Between(plant, source);
    }
  }
  // Between phases: each neighbouring phase's boundary correction, eased out over `blend` or the gap: its
  // height and tilt over `blend`, its horizontal shift and turn over `horizontal_blend`. A planted foot sits
  // where the source's stood on average, and a CMU stance foot slides 10-30 mm, so the foot leaves its plant
  // up to half that off the source's path; caught up over 0.1 s, the foot moved 0.1-0.2 m/s faster than the
  // source's where the source's was still slow (HRP-4C's 10_04 and 12_01 skated 0.05-0.12 over the scaled
  // source's), while a slower return of the height kept swing feet low (its 02_01 0.359 -> 0.528 with both
  // over 0.3 s).
  for (size_t k = 0; k <= own.size() && !own.empty(); ++k) {
    const ContactPhase* before = k > 0 ? own[k - 1] : nullptr;
    const ContactPhase* after = k < own.size() ? own[k] : nullptr;
    const int64_t first = before ? before->end : 0;
    const int64_t last = after ? after->begin : static_cast<int64_t>(frames);  // exclusive
    double span = blend, hspan = horizontal_blend;
    if (before && after) {
      const double gap = time_s[static_cast<size_t>(after->begin)] - time_s[static_cast<size_t>(before->end - 1)];
      span = std::min(blend, gap), hspan = std::min(horizontal_blend, gap);
    }
    const auto add = [](Correction& c, const Correction& edge, double w, double wh) {
      c.translation.head<2>() += wh * edge.translation.head<2>();
      c.translation.z() += w * edge.translation.z();
      c.rotation.head<2>() += w * edge.rotation.head<2>();
      c.rotation.z() += wh * edge.rotation.z();
    };
    for (int64_t t = first; t < last; ++t) {
      Correction& c = correction[static_cast<size_t>(t)];
      const double now = time_s[static_cast<size_t>(t)];
      if (before) {
        const double since = now - time_s[static_cast<size_t>(before->end - 1)];
        add(c, correction[static_cast<size_t>(before->end - 1)], Ease(since / span), Ease(since / hspan));
      }
      if (after) {
        const double until = time_s[static_cast<size_t>(after->begin)] - now;
        add(c, correction[static_cast<size_t>(after->begin)], Ease(until / span), Ease(until / hspan));
      }
    }
  }
  target.resize(frames);
  corrected.assign(frames, false);
  for (size_t t = 0; t < frames; ++t) {
    corrected[t] = correction[t].translation.norm() > 1e-9 || correction[t].rotation.norm() > 1e-9;
    target[t] = Apply(correction[t], free[t]);
    const double lowest = LowestPoint(sole, target[t]);
    if (lowest < 0) {
      target[t].translation().z() -= lowest;
      corrected[t] = true;
    }
  }
}

// Each foot's pose outside contact (contact_enforcement.h, step 0).
// `level`: how far the source was moved down (0 where nothing was).
std::vector<std::vector<Eigen::Isometry3d>> FreePoses(const std::vector<SoleGeometry>& soles, const FootContacts& contacts,
                                                      const std::vector<std::vector<Eigen::Isometry3d>>& tracked,
                                                      const std::vector<std::vector<Eigen::Isometry3d>>& source_feet,
                                                      double& level) {
  level = 0.0;
  if (source_feet.size() != tracked.size()) return tracked;
  std::vector<std::vector<Eigen::Isometry3d>> free = tracked;
  std::vector<double> planted_lowest;
  for (size_t f = 0; f < free.size(); ++f) {
    for (size_t t = 0; t < free[f].size() && t < source_feet[f].size(); ++t) {
      const Eigen::Isometry3d& source = source_feet[f][t];
      if (!source.translation().allFinite()) continue;
      free[f][t].translation() = source.translation();
      if (contacts.planted(static_cast<int64_t>(t), f)) {
        planted_lowest.push_back(LowestPoint(soles[f], free[f][t]));
      }
    }
  }
  if (planted_lowest.empty()) return free;
  level = NearestRankPercentile(std::move(planted_lowest), 0.5);
  for (auto& foot : free) {
    for (Eigen::Isometry3d& pose : foot) pose.translation().z() -= level;
  }
  return free;
}

// Consecutive frames' legs are solved from the previous frame's answer: where joint limits leave a target
// out of reach, several leg configurations come equally close, and a start taken from the tracked motion
// let the solution jump between them (a 0.9 rad hip-yaw step in one frame of CMU 60_10).
// With `first` (the final legs' first solved frame, which has no previous answer), a knee the tracked
// motion left straight on its floor starts bent instead: the leg solver keeps a straight knee straight
// (there the foot cannot move along the leg), and CMU 07_01's first frame kept its right foot 14 cm off
// target, the next frames bending the knee at its speed limit while the planted foot slid. (Bending every
// non-consecutive start, the reach pass's too, moved HRP-4C's legs onto other answers mid-take.)
void ContinueLegs(const std::vector<LegChain>& chains, const Eigen::VectorXd& previous, bool consecutive, bool first,
                  Eigen::VectorXd& q) {
  for (const LegChain& chain : chains) {
    for (size_t k = 0; k < chain.size(); ++k) {
      double& joint = q[chain.q_index[k]];
      if (consecutive) joint = previous[chain.q_index[k]];
      else if (first && chain.branch[k] && joint <= chain.lower[k] + 1e-9) joint = chain.lower[k] + kBranchStart;
    }
  }
}

// A leg carried over straight from the previous frame stays straight in the leg solver (there the foot
// cannot move along the leg), and a plant that comes nearer the hip than the straight leg reaches is then
// never reached: CMU 05_11's last 15 frames, both knees on 0, the planted feet rose 20-33 mm and slid 57 mm.
// Such a leg, left more than a millimetre off its target, is solved again from its branch joints bent
// (within their speed bound), and keeps whichever answer comes nearer. Returns the iterations spent.
int BendStraightKnees(const std::vector<LegChain>& chains, LegSolver& solver,
                      const std::vector<Eigen::Isometry3d>& targets, const std::vector<bool>& active, Eigen::VectorXd& q,
                      const Eigen::VectorXd& before, double step_time, const std::vector<bool>& unbounded,
                      std::vector<bool>& retry) {
  constexpr double kOffTarget = 1e-3;  // m
  Eigen::Matrix<double, 6, 1> error;
  int iterations = 0;
  for (size_t f = 0; f < chains.size(); ++f) {
    if (!active[f]) continue;
    const LegChain& chain = chains[f];
    if ((targets[f].translation() - solver.reached(f).translation()).norm() < kOffTarget) continue;
    const auto on_floor = [&](size_t k) { return chain.branch[k] && q[chain.q_index[k]] <= chain.lower[k] + 1e-9; };
    bool straight = false;
    for (size_t k = 0; k < chain.size(); ++k) straight = straight || on_floor(k);
    if (!straight) continue;
    const double cost = solver.poseError(targets[f], solver.reached(f), error);
    const Eigen::Isometry3d reached = solver.reached(f);
    Eigen::Matrix<double, kMaxLegJoints, 1> kept;
    for (size_t k = 0; k < chain.size(); ++k) {
      kept[static_cast<Eigen::Index>(k)] = q[chain.q_index[k]];
      if (on_floor(k)) q[chain.q_index[k]] = chain.lower[k] + kBranchStart;
    }
    std::fill(retry.begin(), retry.end(), false);
    retry[f] = true;
    iterations += solver.solve(targets, retry, q, 0.0, &before, step_time, &unbounded).iterations;  // dt 0: unbounded
    if (solver.poseError(targets[f], solver.reached(f), error) >= cost) {
      for (size_t k = 0; k < chain.size(); ++k) q[chain.q_index[k]] = kept[static_cast<Eigen::Index>(k)];
      solver.keepReached(f, reached);
    }
  }
  return iterations;
}

// Two box filters over ±w frames (a triangle-weighted mean over ±2w), in place; `zero` is Value's zero.
template <typename Value>
void BoxFilterTwice(std::vector<Value>& values, int64_t w, const Value& zero) {
  const int64_t frames = static_cast<int64_t>(values.size());
  std::vector<Value> box(values.size(), zero);
  for (int pass = 0; pass < 2; ++pass) {
    for (int64_t t = 0; t < frames; ++t) {
      const int64_t a = std::max<int64_t>(0, t - w), b = std::min(frames - 1, t + w);
      Value sum = zero;
      for (int64_t s = a; s <= b; ++s) sum += values[static_cast<size_t>(s)];
      box[static_cast<size_t>(t)] = sum / static_cast<double>(b - a + 1);
    }
    values.swap(box);
  }
}

// A running maximum over ±2w frames, then two box filters over ±w: smooth, and nowhere below `need`.
std::vector<double> SmoothUpperEnvelope(const std::vector<double>& need, int64_t w) {
  const int64_t frames = static_cast<int64_t>(need.size());
  std::vector<double> envelope(need.size());
  for (int64_t t = 0; t < frames; ++t) {
    double most = 0;
    for (int64_t s = std::max<int64_t>(0, t - 2 * w); s <= std::min(frames - 1, t + 2 * w); ++s) most = std::max(most, need[static_cast<size_t>(s)]);
    envelope[static_cast<size_t>(t)] = most;
  }
  BoxFilterTwice(envelope, w, 0.0);
  return envelope;
}

// Outside contact, a free pose has the source's position but the tracked orientation, and where the two
// pitch differently its sole hangs lower than the source's: on CMU 08_07 the right foot swung 4 cm below the
// scaled capture and then skimmed the floor at 3.5 m/s for 20 frames, raised onto it. So an unplanted foot
// is raised until its lowest sole point is as high as the source foot's own (with the source's orientation,
// on the same level), by a smooth envelope of what each frame needs over ±2 `half_width` frames.
// `clearance[f][t]`: that height (0 in contact or without a source orientation), for the leg pass to hold
// where the leg cannot pitch the foot as the free pose asks.
void KeepSourceClearance(const std::vector<SoleGeometry>& soles, const FootContacts& contacts,
                         const std::vector<std::vector<Eigen::Isometry3d>>& source_feet, double level, int64_t half_width,
                         std::vector<std::vector<Eigen::Isometry3d>>& free, std::vector<std::vector<double>>& clearance) {
  clearance.assign(free.size(), std::vector<double>());
  for (size_t f = 0; f < free.size(); ++f) clearance[f].assign(free[f].size(), 0.0);
  if (source_feet.size() != free.size()) return;
  for (size_t f = 0; f < free.size(); ++f) {
    std::vector<double> need(free[f].size(), 0.0);
    for (size_t t = 0; t < free[f].size() && t < source_feet[f].size(); ++t) {
      const Eigen::Isometry3d& source = source_feet[f][t];
      if (!source.translation().allFinite() || !std::isfinite(source.linear()(0, 0))) continue;
      if (contacts.planted(static_cast<int64_t>(t), f)) continue;
      clearance[f][t] = std::max(0.0, LowestPoint(soles[f], source) - level);
      need[t] = std::max(0.0, clearance[f][t] - LowestPoint(soles[f], free[f][t]));
    }
    const std::vector<double> raise = SmoothUpperEnvelope(need, half_width);
    for (size_t t = 0; t < free[f].size(); ++t) free[f][t].translation().z() += raise[t];
  }
}

// The legs' joint speeds over the result against their URDF limits (not --velocity-limit-scale's share of
// them: the motors' own), into the report's overspeed fields. Every frame, solved or not: a frame after the
// last solved one steps back to the tracked motion.
void MeasureOverspeed(const Model& model, const std::vector<LegChain>& chains, const std::vector<double>& time_s,
                      const std::vector<double>& q, ContactEnforcementReport& out) {
  const int64_t nq = model.nq(), frames = static_cast<int64_t>(time_s.size());
  int worst_coordinate = -1;
  for (int64_t t = 1; t < frames; ++t) {
    const double step = time_s[static_cast<size_t>(t)] - time_s[static_cast<size_t>(t - 1)];
    if (!(step > 0)) continue;
    for (const LegChain& chain : chains) {
      for (size_t k = 0; k < chain.size(); ++k) {
        if (!std::isfinite(chain.speed_limit[k]) || !(chain.speed_limit[k] > 0)) continue;
        const size_t i = static_cast<size_t>(chain.q_index[k]);
        const double ratio = std::abs(q[static_cast<size_t>(t * nq) + i] - q[static_cast<size_t>((t - 1) * nq) + i]) /
                             (step * chain.speed_limit[k]);
        // A hair over 1 is the bounded solve's own rounding, not a joint driven past its motor.
        if (ratio > 1.0 + 1e-6) ++out.overspeed_joint_frames;
        if (ratio > out.worst_speed_ratio) {
          out.worst_speed_ratio = ratio, out.worst_speed_frame = t, worst_coordinate = chain.q_index[k];
        }
      }
    }
  }
  if (worst_coordinate >= 0) {
    out.worst_speed_joint = model.coordinateNames()[static_cast<size_t>(worst_coordinate)];
    out.worst_speed_time = time_s[static_cast<size_t>(out.worst_speed_frame)];
  }
}

// The planted legs' joints against their position limits over the result, into the report's stance-limit
// fields. chains[f] is foot f's leg.
void MeasureLimitedStance(const Model& model, const std::vector<LegChain>& chains, const FootContacts& contacts,
                          const std::vector<double>& q, ContactEnforcementReport& out) {
  const int64_t nq = model.nq(), frames = static_cast<int64_t>(q.size()) / nq;
  std::vector<int64_t> per_coordinate(static_cast<size_t>(nq), 0);
  for (int64_t t = 0; t < frames; ++t) {
    for (size_t f = 0; f < chains.size(); ++f) {
      if (!contacts.planted(t, f)) continue;
      ++out.planted_foot_frames;
      bool limited = false;
      for (const int i : chains[f].q_index) {
        const double value = q[static_cast<size_t>(t * nq + i)];
        if (value - model.qLower()[i] < kStanceLimitBand || model.qUpper()[i] - value < kStanceLimitBand) {
          limited = true;
          ++per_coordinate[static_cast<size_t>(i)];
        }
      }
      if (limited) ++out.limited_stance_frames;
    }
  }
  const auto most = std::max_element(per_coordinate.begin(), per_coordinate.end());
  if (most != per_coordinate.end() && *most > 0) {
    out.most_limited_joint = model.coordinateNames()[static_cast<size_t>(most - per_coordinate.begin())];
    out.most_limited_joint_frames = *most;
  }
}

using Vector6d = Eigen::Matrix<double, 6, 1>;  // a base correction: rotation vector, translation (ground frame)

Correction AsCorrection(const Vector6d& correction) { return {correction.tail<3>(), correction.head<3>()}; }

constexpr double kClearanceSmoothing = 0.025;  // s: half the window over which a swing foot's raise is smoothed
constexpr double kClearanceTolerance = 1e-3;   // m a reached swing sole may hang under the source's
// How fast a swing foot's clearance raise may grow from its plant, so that the raise starts and ends on
// the plant instead of jumping there: at most kClearanceRiseAcceleration (m/s², about 2 g) up to
// kClearanceRiseSpeed (m/s; a walking foot leaves the floor at 0.5-1 m/s). Bounded by speed alone, a raise
// landed CMU 02_01's first step 8.8 mm above its plant one frame before it, the knee stepping 16 rad/s.
constexpr double kClearanceRiseSpeed = 1.0;
constexpr double kClearanceRiseAcceleration = 20.0;

// The most a clearance raise may be `elapsed` seconds from a plant.
double ClearanceRiseCap(double elapsed) {
  constexpr double kRamp = kClearanceRiseSpeed / kClearanceRiseAcceleration;  // s to reach full speed
  if (elapsed < kRamp) return 0.5 * kClearanceRiseAcceleration * elapsed * elapsed;
  return kClearanceRiseSpeed * (elapsed - 0.5 * kRamp);
}
constexpr double kPlantPositionTolerance = 1e-3;  // m: a planted foot this close to its plant needs no base move
constexpr double kPlantAngleTolerance = 0.5 * M_PI / 180.0;
// rad: the most the pelvis turns for a plant. Where a plant is out of reach however the pelvis turns (CMU
// 94_07's deep squat past G1's ankle), the search kept turning and tipped the robot over by up to 180°; the
// cap leaves the rest of that plant to the leg solves (94_07's drift p95 81 -> 41 mm). The 31 other CMU walks
// and dances onto G1 turn at most 31° with G1's [joint_ranges], except 94_15 (63°, unchanged in its drift).
constexpr double kMaxBaseTurn = 0.8;

// Whether a foot at `reached` is on its plant `target`, within the tolerances above.
bool OnPlant(const Eigen::Isometry3d& target, const Eigen::Isometry3d& reached) {
  const Correction off = Between(target, reached);
  return off.translation.norm() < kPlantPositionTolerance && off.rotation.norm() < kPlantAngleTolerance;
}

// The base link's pose at frame_q (returned), and each leg root's pose relative to it (`relative`): what both
// pelvis searches below move the roots with.
Eigen::Isometry3d RootsOnBase(TreeKinematics& tree, int base_link, const std::vector<LegChain>& chains,
                              const Eigen::VectorXd& frame_q, std::vector<Eigen::Isometry3d>& relative) {
  tree.setQ(frame_q);
  const Eigen::Isometry3d base = tree.linkPose(base_link);
  for (size_t f = 0; f < chains.size(); ++f) relative[f] = base.inverse() * tree.linkPose(chains[f].root_link);
  return base;
}

// The planted legs of both pelvis searches below, with the base at `base` moved by `correction`: each leg's
// root is the moved base times its `relative` pose, the legs are solved from `start` (within their speed
// bounds about `previous` over `dt` when given, `unbounded` exempting some), and their pose errors
// (LegSolver::poseError) are stacked into r. `roots` and `legs` are the caller's scratch; `legs` holds the
// answer. Returns whether every planted foot is on its plant.
bool SolvePlantedLegs(LegSolver& solver, const Eigen::Isometry3d& base, const Vector6d& correction,
                      const std::vector<Eigen::Isometry3d>& relative, const std::vector<Eigen::Isometry3d>& targets,
                      const std::vector<bool>& planted, int rows, const Eigen::VectorXd& start, const Eigen::VectorXd* previous,
                      double dt, const std::vector<bool>* unbounded, std::vector<Eigen::Isometry3d>& roots,
                      Eigen::VectorXd& legs, Eigen::VectorXd& r) {
  const Eigen::Isometry3d moved = Apply(AsCorrection(correction), base);
  for (size_t f = 0; f < relative.size(); ++f) roots[f] = moved * relative[f];
  legs = start;
  solver.solveFromRoots(roots, targets, planted, legs, 0.0, previous, dt, unbounded);
  r.resize(rows);
  Eigen::Matrix<double, 6, 1> error;
  int row = 0;
  bool on_plants = true;
  for (size_t f = 0; f < relative.size(); ++f) {
    if (!planted[f]) continue;
    solver.poseError(targets[f], solver.reached(f), error);
    r.segment<6>(row) = error, row += 6;
    on_plants = on_plants && OnPlant(targets[f], solver.reached(f));
  }
  return on_plants;
}

// m²: the legs' least-squares steps in PlantedLegsJacobian are damped by this, so that a leg near full
// extension does not take back, on paper, a move its joints would have to spin to follow.
constexpr double kLegRegularisation = 1e-8;

// The Jacobian of SolvePlantedLegs' residual with respect to the base correction, at the correction its
// legs were last solved for (rows as the residual's, columns as Vector6d's). Moving the base carries each
// planted foot rigidly, and the leg's free joints (LegSolver::freeJacobian) take back what they can: to first
// order the part of that rigid motion within their columns' span, so what remains is the rest. It replaces
// finite differences, which solved the legs six more times per iteration (a quarter of the stage on CMU
// dances) and, their nudges' legs started from another point than the current one's, measured mostly that
// difference: columns of 70-400 where this gives 0.01-0.08 on the enforced Kimodo dance.
void PlantedLegsJacobian(const LegSolver& solver, const Eigen::Isometry3d& base, const Vector6d& correction,
                         const std::vector<bool>& planted, Eigen::MatrixXd& jacobian) {
  jacobian.resize(6 * std::count(planted.begin(), planted.end(), true), 6);
  // How a change of the correction's rotation vector turns the base on top of its present turn.
  const Eigen::Matrix3d left = RotationLeftJacobian(correction.head<3>());
  const Eigen::Vector3d base_origin = base.translation() + correction.tail<3>();
  const double angle_scale = solver.angleScale();
  Eigen::Matrix<double, 6, 6> rigid;
  int row = 0;
  for (size_t f = 0; f < planted.size(); ++f) {
    if (!planted[f]) continue;
    // The pose error (angle_scale × rotation vector, target − position) as the base moves the foot rigidly.
    const Eigen::Vector3d lever = solver.reached(f).translation() - base_origin;
    rigid.topLeftCorner<3, 3>() = -angle_scale * left;
    rigid.topRightCorner<3, 3>().setZero();
    rigid.bottomLeftCorner<3, 3>() = CrossMatrix(lever) * left;
    rigid.bottomRightCorner<3, 3>() = -Eigen::Matrix3d::Identity();
    // What the free joints take back: the least-squares leg step against that motion.
    const LegSolver::ChainJacobian& leg = solver.freeJacobian(f);
    Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxLegJoints, kMaxLegJoints> normal =
        leg.transpose().lazyProduct(leg);
    normal.diagonal().array() += kLegRegularisation;
    jacobian.middleRows<6>(row) = rigid - leg.lazyProduct(normal.llt().solve(leg.transpose().lazyProduct(rigid)));
    row += 6;
  }
}

// Levenberg-Marquardt over a base correction, shared by the two pelvis searches below. `evaluate(c, r, J)`
// fills the residual r at c and its Jacobian J (PlantedLegsJacobian) and returns ‖r‖² + kBasePrior ‖c −
// centre‖²; each candidate step passes through `filter`; the search stops after `iterations`, when `done()`,
// or when no step lowers the cost. On entry `correction`, `residual`, `jacobian` and `cost` are the start's;
// on exit the best found's. The caller's legs are left at the last candidate evaluated, which may be another.
constexpr double kBasePrior = 1e-6;  // the pull towards `centre`

template <typename Evaluate, typename Filter, typename Done>
void DescendOverBase(const Evaluate& evaluate, const Vector6d& centre, const Filter& filter, const Done& done, int iterations,
                     Vector6d& correction, Eigen::VectorXd& residual, Eigen::MatrixXd& jacobian, double& cost,
                     Eigen::VectorXd& trial, Eigen::MatrixXd& trial_jacobian) {
  double damping = 1e-4;
  for (int iteration = 0; iteration < iterations && !done(); ++iteration) {
    const Eigen::Matrix<double, 6, 6> normal = jacobian.transpose() * jacobian;
    const Vector6d gradient = jacobian.transpose() * residual + kBasePrior * (correction - centre);
    bool improved = false;
    for (int attempt = 0; attempt < 6 && !improved; ++attempt) {
      Eigen::Matrix<double, 6, 6> damped = normal;
      damped.diagonal().array() += damping + kBasePrior;
      Vector6d candidate = correction - damped.ldlt().solve(gradient);
      filter(candidate);
      const double candidate_cost = evaluate(candidate, trial, trial_jacobian);
      if (candidate_cost < cost) {
        improved = true, cost = candidate_cost, correction = candidate;
        residual.swap(trial), jacobian.swap(trial_jacobian);
        damping = std::max(damping / 3.0, 1e-9);
      } else {
        damping *= 10.0;
      }
    }
    if (!improved) break;
  }
}

// Contacts rank above the pelvis task (issue 17): where a planted foot is out of its leg's reach from the
// tracked pelvis because a leg joint is on its limit (a dancer turning on one foot further than the G1's
// hip yaw and roll allow: CMU 05_02's left plant slid 41 mm and turned 30° with the hip roll on -0.52 rad),
// the pelvis moves instead, by the smallest rotation and translation with which every planted leg reaches
// its plant (Levenberg–Marquardt over the base's six velocities, each evaluation the planted legs solved
// from their moved roots). The corrections are smoothed in time like the lowering, and the pass repeated
// on what the smoothing left, so the upper body turns with the pelvis smoothly instead of jumping.
std::vector<Vector6d> BaseCorrections(const Model& model, const BaseMover& mover, TreeKinematics& tree, LegSolver& solver, const std::vector<LegChain>& chains,
                                      const FootContacts& contacts, const std::vector<std::vector<Eigen::Isometry3d>>& target,
                                      const std::vector<double>& lowering, int64_t vertical_coordinate, int64_t half_width,
                                      const std::vector<double>& q) {
  const int64_t nq = model.nq(), frames = static_cast<int64_t>(lowering.size());
  const size_t foot_count = chains.size();
  std::vector<Vector6d> total(static_cast<size_t>(frames), Vector6d::Zero());
  const int base_link = mover.link();
  if (base_link < 0 || contacts.feet == 0) return total;
  std::vector<Vector6d> need(static_cast<size_t>(frames));
  std::vector<bool> planted(foot_count);
  std::vector<Eigen::Isometry3d> relative(foot_count), roots(foot_count), frame_targets(foot_count);
  Eigen::VectorXd frame_q(nq), legs(nq), previous_legs(nq), scratch_q(nq);
  Eigen::VectorXd residual, trial;
  Eigen::MatrixXd jacobian, trial_jacobian;
  constexpr int kPasses = 6, kIterations = 12;
  for (int pass = 0; pass < kPasses; ++pass) {
    bool any = false;
    int64_t previous_frame = -2;
    for (int64_t t = 0; t < frames; ++t) {
      Vector6d& out = need[static_cast<size_t>(t)];
      out.setZero();
      int rows = 0;
      for (size_t f = 0; f < foot_count; ++f) {
        planted[f] = contacts.planted(t, f);
        frame_targets[f] = target[f][static_cast<size_t>(t)];
        rows += planted[f] ? 6 : 0;
      }
      if (rows == 0) continue;
      frame_q = Eigen::Map<const Eigen::VectorXd>(&q[static_cast<size_t>(t * nq)], nq);
      if (vertical_coordinate >= 0) frame_q[vertical_coordinate] -= lowering[static_cast<size_t>(t)];
      mover.apply(total[static_cast<size_t>(t)], frame_q);
      const Eigen::Isometry3d base = RootsOnBase(tree, base_link, chains, frame_q, relative);
      // The LM cost with the base moved by `correction`, the legs solved from frame_q's; `reached` and `legs`
      // say where they got.
      bool reached = true;
      const auto evaluate = [&](const Vector6d& correction, Eigen::VectorXd& r, Eigen::MatrixXd& j) {
        reached = SolvePlantedLegs(solver, base, correction, relative, frame_targets, planted, rows, frame_q, nullptr,
                                   0.0, nullptr, roots, legs, r);
        PlantedLegsJacobian(solver, base, correction, planted, j);
        return r.squaredNorm() + kBasePrior * correction.squaredNorm();
      };
      // Where to start the legs. A plant the previous frame's legs reach without a move needs none: the final
      // solves continue from the previous frame, and from a straight tracked knee a solve stops short where
      // they reach (CMU 02_01's pelvis moved in 154 frames for nothing). But the search starts from the
      // tracked legs: from a previous answer held on a hip-yaw limit, CMU 94_07's deep-squat pivots asked for
      // moves that left its plants further off.
      Vector6d correction = Vector6d::Zero();
      double cost = evaluate(correction, residual, jacobian);
      if (!reached && t - 1 == previous_frame) {
        scratch_q = frame_q;
        ContinueLegs(chains, previous_legs, true, false, frame_q);
        evaluate(correction, trial, trial_jacobian);
        frame_q = scratch_q;
      }
      if (reached) {
        previous_legs = legs, previous_frame = t;
        continue;
      }
      DescendOverBase(evaluate, Vector6d::Zero(), [](Vector6d&) {}, [&] { return reached; }, kIterations, correction, residual,
                      jacobian, cost, trial, trial_jacobian);
      evaluate(correction, residual, jacobian);  // the legs at the correction taken, for the next frame's start
      previous_legs = legs, previous_frame = t;
      out = correction;
      any = true;
    }
    if (!any) break;
    // Smoothed like the lowering, so the pelvis turns into and out of a move instead of jumping.
    BoxFilterTwice(need, half_width, Vector6d::Zero().eval());
    for (int64_t t = 0; t < frames; ++t) {
      Vector6d& sum = total[static_cast<size_t>(t)];
      sum += need[static_cast<size_t>(t)];
      const double turn = sum.head<3>().norm();
      if (turn > kMaxBaseTurn) sum.head<3>() *= kMaxBaseTurn / turn;
    }
  }
  return total;
}

// HoldPlantsWithinSpeed's Levenberg-Marquardt iterations per frame (10 took HRP-4C's 32 CMU walks and dances
// 20 % longer for a stance drift median of 12.9 mm against 12.6 at 4), and the farthest its pelvis moves from
// the tracking: further, HRP-4C's pelvis lagged its target by up to 0.8 m on CMU 94_06.
constexpr int kHoldIterations = 4;
constexpr double kMaxHoldShift = 0.1;  // m

// How far a pelvis move may change from one frame to the next: 0.01 rad and 5 mm (1.2 rad/s, 0.6 m/s at
// 120 Hz), so that the pelvis, the upper body with it, does not jump.
void LimitBaseStep(Vector6d& step) {
  constexpr double kTurn = 0.01, kShift = 0.005;
  const double turn = step.head<3>().norm(), shift = step.tail<3>().norm();
  if (turn > kTurn) step.head<3>() *= kTurn / turn;
  if (shift > kShift) step.tail<3>() *= kShift / shift;
}

// Scratch of HoldPlantsWithinSpeed, sized once per take: nothing is allocated per frame.
struct HoldScratch {
  std::vector<Eigen::Isometry3d> relative, roots;
  Eigen::VectorXd legs, residual, trial;
  Eigen::MatrixXd jacobian, trial_jacobian;
};

// The legs' speed limits rank below contacts too: where a planted leg, each joint within its velocity limit
// of the previous frame, cannot hold its plant from the pelvis the pass above left (HRP-4C's legs turn at
// 1.9-3 rad/s; a person's pelvis moves faster over a planted foot), the pelvis moves this frame by the least
// turn and shift with which every planted leg holds its plant within those limits (Levenberg-Marquardt as in
// BaseCorrections, the legs solved with their speed bounds), and the upper body with it; `carried` is the
// move the previous frames made, which the search pulls back towards none. Returns whether it moved (by
// `moved`); frame_q's legs are then to be solved again from the moved pelvis.
bool HoldPlantsWithinSpeed(const BaseMover& mover, TreeKinematics& tree, LegSolver& solver, const std::vector<LegChain>& chains,
                           const std::vector<Eigen::Isometry3d>& targets, const std::vector<bool>& planted,
                           const Eigen::VectorXd& before, double step_time, const std::vector<bool>& unbounded,
                           const Vector6d& carried, HoldScratch& scratch, Eigen::VectorXd& frame_q, Vector6d& moved) {
  moved.setZero();
  if (!mover.canMove() || step_time <= 0) return false;
  int rows = 0;
  bool missing = false;
  for (size_t f = 0; f < chains.size(); ++f) {
    if (!planted[f]) continue;
    rows += 6;
    missing = missing || !OnPlant(targets[f], solver.reached(f));
  }
  if (!missing) return false;
  scratch.relative.resize(chains.size()), scratch.roots.resize(chains.size());
  const Eigen::Isometry3d base = RootsOnBase(tree, mover.link(), chains, frame_q, scratch.relative);
  const auto evaluate = [&](const Vector6d& correction, Eigen::VectorXd& r, Eigen::MatrixXd& j) {
    SolvePlantedLegs(solver, base, correction, scratch.relative, targets, planted, rows, frame_q, &before, step_time,
                     &unbounded, scratch.roots, scratch.legs, r);
    PlantedLegsJacobian(solver, base, correction, planted, j);
    return r.squaredNorm() + kBasePrior * (carried + correction).squaredNorm();
  };
  Vector6d correction = Vector6d::Zero();
  Eigen::VectorXd& residual = scratch.residual;
  double cost = evaluate(correction, residual, scratch.jacobian);
  const double start_cost = cost;
  // Held as soon as a step brings the plants within a millimetre (not before the first: a plant may miss by
  // its angle alone, which that norm does not see).
  bool stepped = false;
  const auto held = [&] { return std::exchange(stepped, true) && residual.norm() < kPlantPositionTolerance; };
  DescendOverBase(evaluate, -carried, LimitBaseStep, held, kHoldIterations, correction, residual, scratch.jacobian, cost,
                  scratch.trial, scratch.trial_jacobian);
  if (!(cost < start_cost) || (carried + correction).head<3>().norm() > kMaxBaseTurn ||
      (carried + correction).tail<3>().norm() > kMaxHoldShift) {
    return false;
  }
  mover.apply(correction, frame_q);
  moved = correction;
  return true;
}

// A planted foot its leg leaves above the floor, no sole point touching it: a leg at full stretch from where
// the passes above put the pelvis, or one too slow to bring the foot down by the phase's first frames. The
// sole belongs on the floor (issue 17: contacts rank above the pelvis task), so the base comes down by the
// lift, in up to kLiftRounds rounds, the legs re-solved each time, but only while no other foot pays for
// it (a planted one sliding off its plan, any going deeper into the floor or, unplanted, further from its
// target). Over the 32 CMU walks and dances, phases whose planted sole rose more than 5 mm: G1 36 -> 19,
// HRP-4C 51 -> 45 (tools/report/contact_check.py); the pelvis's vertical acceleration, p99 over a take,
// median over the takes, 38 -> 21 and 104 -> 96 m/s². Left: lifts where lowering would move another foot
// (HRP-4C's late touchdowns, 13-18 mm up at a walk's first planted frame while the other leg lifts off;
// G1 on CMU 03_04 at 6.9 s, 24 mm) or where the floor rounds below raise the base for another foot
// afterwards (G1 on CMU 94_15 at 5.2 s: a kicking leg that cannot get its foot out of the floor, and
// the planted foot rises 48 mm). Returns the leg solver's iterations.
constexpr double kLiftTolerance = 1e-3;  // m a planted sole's lowest point may stay above the floor
constexpr int kLiftRounds = 3;

// Per foot, how far the legs leave it off its target: its sole centre's distance (horizontal for a planted
// foot, whose height is `lift`'s) and its depth under the floor; and the planted feet's largest lift.
struct FootMisses {
  std::vector<double> slip, depth;
  double lift = 0.0;
};

void MeasureFootMisses(const LegSolver& solver, const std::vector<SoleGeometry>& soles, const FootContacts& contacts, int64_t t,
                       const std::vector<Eigen::Isometry3d>& targets, const std::vector<bool>& active, FootMisses& misses) {
  misses.slip.assign(soles.size(), 0.0);
  misses.depth.assign(soles.size(), 0.0);
  misses.lift = 0.0;
  for (size_t f = 0; f < soles.size(); ++f) {
    if (!active[f]) continue;
    const Eigen::Isometry3d& reached = solver.reached(f);
    const double lowest = LowestPoint(soles[f], reached);
    const Eigen::Vector3d off = (reached * soles[f].centre) - (targets[f] * soles[f].centre);
    misses.depth[f] = std::max(0.0, -lowest);
    if (contacts.planted(t, f)) {
      misses.slip[f] = off.head<2>().norm();
      misses.lift = std::max(misses.lift, lowest);
    } else {
      misses.slip[f] = off.norm();
    }
  }
}

// `kept`, `misses` and `lowered_misses` are the caller's scratch (sized once: nothing allocated per frame).
int LowerOntoLiftedPlants(LegSolver& solver, const std::vector<SoleGeometry>& soles, const FootContacts& contacts, int64_t t,
                          const std::vector<Eigen::Isometry3d>& targets, const std::vector<bool>& active,
                          const Eigen::VectorXd& before, double step_time, const std::vector<bool>& unbounded,
                          int64_t vertical_coordinate, Eigen::VectorXd& frame_q, Eigen::VectorXd& kept,
                          FootMisses& misses, FootMisses& lowered_misses, ContactEnforcementReport& out) {
  int iterations = 0;
  MeasureFootMisses(solver, soles, contacts, t, targets, active, misses);
  bool lowered = false;
  for (int round = 0; round < kLiftRounds && misses.lift > kLiftTolerance; ++round) {
    kept = frame_q;
    frame_q[vertical_coordinate] -= misses.lift;
    iterations += solver.solve(targets, active, frame_q, 0.0, &before, step_time, &unbounded).iterations;
    MeasureFootMisses(solver, soles, contacts, t, targets, active, lowered_misses);
    // Only if no other foot pays for it: a slow leg (HRP-4C's) asked to bend further slid its planted
    // foot instead; a leg just lifted off (G1 on CMU 03_04 at 6.86 s) jumped 8 cm sideways for a frame.
    bool worse = !(lowered_misses.lift < misses.lift);
    for (size_t f = 0; f < soles.size(); ++f) {
      worse = worse || lowered_misses.slip[f] > misses.slip[f] + kLiftTolerance ||
              lowered_misses.depth[f] > std::max(misses.depth[f], kFloorTolerance);
    }
    if (worse) {
      frame_q = kept;
      iterations += solver.solve(targets, active, frame_q, 0.0, &before, step_time, &unbounded).iterations;
      break;
    }
    out.max_lowering_onto_plant = std::max(out.max_lowering_onto_plant, misses.lift);
    lowered = true;
    std::swap(misses, lowered_misses);
  }
  out.lowered_onto_plant_frames += lowered ? 1 : 0;
  return iterations;
}

// Touchdown: the plant is where the foot touched down. Where the leg's speed limits kept the foot from the
// planned plant at a phase's first frame `t` (HRP-4C's legs, 1.9-3 rad/s, cannot swing at a person's pace),
// the plant moves in the floor's plane to where the foot landed, for the whole phase, and the move eases
// out over `blend` after it; the foot then stays where it landed instead of sliding on to the plan. Returns the plants moved.
int PlantWhereTouchedDown(const std::vector<SoleGeometry>& soles, const FootContacts& contacts,
                          const std::vector<std::vector<int>>& phase_begins, const std::vector<double>& time_s, double blend,
                          const LegSolver& solver, const std::vector<bool>& active, int64_t t,
                          std::vector<std::vector<Eigen::Isometry3d>>& target, std::vector<std::vector<bool>>& changed) {
  const int64_t frames = static_cast<int64_t>(time_s.size());
  int moved = 0;
  for (size_t f = 0; f < soles.size(); ++f) {
    const int p = phase_begins[f][static_cast<size_t>(t)];
    if (p < 0 || !active[f]) continue;
    const Eigen::Isometry3d& reached = solver.reached(f);
    const Eigen::Isometry3d& plan = target[f][static_cast<size_t>(t)];
    if (OnPlant(plan, reached)) continue;
    // The plan moves in the floor's plane, its sole centre onto the reached one's and its heading to the
    // reached heading; each frame keeps the plan's own pitch (a heel strike's roll, then flat). Laid flat at
    // the touchdown pose instead, a plan rolled at its first frame had that roll undone on every later,
    // already flat, frame: HRP-4C's feet tilted the other way and slid 13.5 mm (CMU 05_02).
    const Eigen::Vector3d from = plan * soles[f].centre, to = reached * soles[f].centre;
    const Eigen::Matrix3d turn =
        Eigen::AngleAxisd(Yaw(reached.linear(), soles[f]) - Yaw(plan.linear(), soles[f]), Eigen::Vector3d::UnitZ()).toRotationMatrix();
    Eigen::Isometry3d move = Eigen::Isometry3d::Identity();
    move.linear() = turn;
    move.translation() = Eigen::Vector3d(to.x(), to.y(), 0.0) - turn * Eigen::Vector3d(from.x(), from.y(), 0.0);
    const ContactPhase& phase = contacts.phases[static_cast<size_t>(p)];
    for (int64_t s = t; s < phase.end; ++s) target[f][static_cast<size_t>(s)] = move * target[f][static_cast<size_t>(s)];
    const Correction shift = Between(target[f][static_cast<size_t>(phase.end - 1)], move.inverse() * target[f][static_cast<size_t>(phase.end - 1)]);
    const double end_time = time_s[static_cast<size_t>(phase.end - 1)];
    for (int64_t s = phase.end; s < frames && time_s[static_cast<size_t>(s)] - end_time < blend; ++s) {
      if (contacts.at(s, static_cast<int>(f))) break;
      const double w = Ease((time_s[static_cast<size_t>(s)] - end_time) / blend);
      target[f][static_cast<size_t>(s)] = Apply({w * shift.translation, w * shift.rotation}, target[f][static_cast<size_t>(s)]);
      changed[f][static_cast<size_t>(s)] = true;
    }
    ++moved;
  }
  return moved;
}

// The free poses' clearance (KeepSourceClearance) assumed the legs pitch the swing feet as asked. Where an
// ankle limit leaves a foot pitched further (HRP-4C's ankle pitch ends at 0.5 rad while its knee folds 1.2 rad
// in swing, lowered pelvis and all: CMU 12_03's feet hung toes down 3-7 cm under the scaled source's and
// dragged over the floor at walking pace), the foot must rise by what its reached sole lacks. Raised frame by
// frame in the final pass, the velocity-bounded legs sawed up and down 15 mm a frame, so the legs are first
// solved for every unplanted frame where they will stand (lowering and pelvis moves applied, speed
// unbounded), what each reached sole lacks of its target's own height (at most the source's clearance) is
// smoothed like the lowering into a raise of the target, and the raise may grow no faster than
// ClearanceRiseCap from the foot's last and next planted frames, so a foot leaves and meets its plant
// smoothly. Returns the frames raised by more than kClearanceTolerance.
int64_t RaiseSwingFeetToClearance(LegSolver& solver, const std::vector<LegChain>& chains, const BaseMover& mover,
                                  const std::vector<SoleGeometry>& soles, const FootContacts& contacts,
                                  const std::vector<std::vector<double>>& clearance, const std::vector<double>& lowering,
                                  const std::vector<Vector6d>& base_correction, int64_t vertical_coordinate, int64_t nq,
                                  const std::vector<double>& q, const std::vector<double>& time_s, int64_t half_width,
                                  std::vector<std::vector<Eigen::Isometry3d>>& target, std::vector<std::vector<bool>>& changed) {
  const size_t foot_count = chains.size();
  const int64_t frames = static_cast<int64_t>(time_s.size());
  std::vector<std::vector<double>> lacking(foot_count, std::vector<double>(static_cast<size_t>(frames), 0.0));
  std::vector<Eigen::Isometry3d> frame_targets(foot_count);
  std::vector<bool> active(foot_count);
  Eigen::VectorXd frame_q(nq), previous(nq);
  int64_t previous_frame = -2;
  bool any_lacking = false;
  for (int64_t t = 0; t < frames; ++t) {
    bool any = false;
    for (size_t f = 0; f < foot_count; ++f) {
      active[f] = !contacts.planted(t, f) && clearance[f][static_cast<size_t>(t)] > 0.0;
      frame_targets[f] = target[f][static_cast<size_t>(t)];
      any = any || active[f];
    }
    if (!any) continue;
    frame_q = Eigen::Map<const Eigen::VectorXd>(&q[static_cast<size_t>(t * nq)], nq);
    if (vertical_coordinate >= 0) frame_q[vertical_coordinate] -= lowering[static_cast<size_t>(t)];
    if (base_correction[static_cast<size_t>(t)].squaredNorm() > 0) mover.apply(base_correction[static_cast<size_t>(t)], frame_q);
    ContinueLegs(chains, previous, t - 1 == previous_frame, false, frame_q);
    solver.solve(frame_targets, active, frame_q, 0.0);
    previous = frame_q, previous_frame = t;
    for (size_t f = 0; f < foot_count; ++f) {
      if (!active[f]) continue;
      const double wanted = std::min(clearance[f][static_cast<size_t>(t)], LowestPoint(soles[f], frame_targets[f]));
      const double short_by = wanted - LowestPoint(soles[f], solver.reached(f));
      if (short_by > kClearanceTolerance) lacking[f][static_cast<size_t>(t)] = short_by, any_lacking = true;
    }
  }
  if (!any_lacking) return 0;
  std::vector<bool> raised(static_cast<size_t>(frames), false);
  for (size_t f = 0; f < foot_count; ++f) {
    const std::vector<double> raise = SmoothUpperEnvelope(lacking[f], half_width);
    // Time since the foot's last planted frame and until its next one (infinite without).
    std::vector<double> since(static_cast<size_t>(frames), std::numeric_limits<double>::infinity()), until = since;
    for (int64_t t = 0, last = -1; t < frames; ++t) {
      if (contacts.planted(t, f)) last = t;
      if (last >= 0) since[static_cast<size_t>(t)] = time_s[static_cast<size_t>(t)] - time_s[static_cast<size_t>(last)];
    }
    for (int64_t t = frames - 1, next = -1; t >= 0; --t) {
      if (contacts.planted(t, f)) next = t;
      if (next >= 0) until[static_cast<size_t>(t)] = time_s[static_cast<size_t>(next)] - time_s[static_cast<size_t>(t)];
    }
    for (int64_t t = 0; t < frames; ++t) {
      const size_t i = static_cast<size_t>(t);
      if (contacts.planted(t, f)) continue;
      const double lift = std::min(raise[i], ClearanceRiseCap(std::min(since[i], until[i])));
      if (!(lift > 1e-9)) continue;
      target[f][i].translation().z() += lift;
      changed[f][i] = true;
      if (lift > kClearanceTolerance) raised[i] = true;
    }
  }
  return std::count(raised.begin(), raised.end(), true);
}

}  // namespace

bool ContactEnforcementOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& message) {
    if (error) *error = message;
    return false;
  };
  if (!(blend >= 0)) return fail("--contact-blend must be >= 0 s");
  if (!(horizontal_blend >= 0)) return fail("--contact-blend-horizontal must be >= 0 s");
  if (!(max_roll >= 0 && max_roll <= M_PI / 2)) return fail("--max-roll must be in [0, pi/2] rad");
  if (!(stance_knee >= 0 && stance_knee < 1.5)) return fail("--stance-knee must be in [0, 1.5) rad");
  if (!(max_lowering >= 0 && max_lowering < 1)) return fail("--max-lowering must be in [0, 1) (a fraction of the leg)");
  if (!(lowering_smoothing >= 0)) return fail("--lowering-smoothing must be >= 0 s");
  if (!(base_smoothing >= 0)) return fail("--base-smoothing must be >= 0 s");
  if (!(velocity_limit_scale >= 0)) return fail("--velocity-limit-scale must be >= 0 (0: unbounded)");
  return true;
}

void EnforceContacts(const Model& model, Workspace& workspace, const std::vector<RobotFoot>& feet,
                     const FootContacts& contacts, const std::vector<std::vector<Eigen::Isometry3d>>& source_feet,
                     int64_t vertical_coordinate, const std::vector<double>& time_s,
                     const std::string& map_file, const ContactEnforcementOptions& options, std::vector<double>& q,
                     ContactEnforcementReport* report) {
  ContactEnforcementReport local;
  ContactEnforcementReport& out = report ? *report : local;
  const int64_t nq = model.nq(), frames = static_cast<int64_t>(time_s.size());
  const size_t foot_count = feet.size();
  if (foot_count == 0 || frames == 0) return;
  std::vector<LegChain> chains;
  std::vector<SoleGeometry> soles;
  for (const RobotFoot& foot : feet) {
    chains.push_back(FindLegChain(model, workspace, foot.link, map_file));
    soles.push_back(SoleOf(foot));
  }

  // Places the robot for the tracked feet and the pelvis searches: the tree's own forward kinematics, not a
  // Simbody setQ (with Debian's state checks), which was a tenth of CMU dance 05_11's whole stage.
  TreeKinematics tree(model);

  // The tracked motion's feet and hips.
  std::vector<std::vector<Eigen::Isometry3d>> tracked(foot_count), target(foot_count);
  std::vector<std::vector<Eigen::Vector3d>> hip(foot_count);
  // corrected: moved by a contact or out of the floor; changed: anywhere the target is not the tracked pose.
  std::vector<std::vector<bool>> corrected(foot_count), changed(foot_count);
  for (size_t f = 0; f < foot_count; ++f) tracked[f].resize(static_cast<size_t>(frames)), hip[f].resize(static_cast<size_t>(frames));
  Eigen::VectorXd frame_q(nq);
  for (int64_t t = 0; t < frames; ++t) {
    frame_q = Eigen::Map<const Eigen::VectorXd>(&q[static_cast<size_t>(t * nq)], nq);
    tree.setQ(frame_q);
    for (size_t f = 0; f < foot_count; ++f) {
      tracked[f][static_cast<size_t>(t)] = tree.linkPose(chains[f].foot_link);
      hip[f][static_cast<size_t>(t)] = tree.linkPose(chains[f].hip_link).translation();
    }
  }
  double level = 0.0;
  std::vector<std::vector<Eigen::Isometry3d>> free = FreePoses(soles, contacts, tracked, source_feet, level);
  const double dt = frames > 1 ? (time_s.back() - time_s.front()) / static_cast<double>(frames - 1) : 1.0;
  const int64_t clearance_half_width = static_cast<int64_t>(std::lround(kClearanceSmoothing / std::max(dt, 1e-9)));
  std::vector<std::vector<double>> clearance;
  KeepSourceClearance(soles, contacts, source_feet, level, clearance_half_width, free, clearance);
  for (size_t f = 0; f < foot_count; ++f) {
    FootTargets(soles[f], free[f], contacts.phases, static_cast<int>(f), time_s, options.blend, options.horizontal_blend, options.max_roll,
                target[f], corrected[f]);
    changed[f].resize(static_cast<size_t>(frames));
    for (int64_t t = 0; t < frames; ++t) {
      const Correction moved = Between(target[f][static_cast<size_t>(t)], tracked[f][static_cast<size_t>(t)]);
      changed[f][static_cast<size_t>(t)] = moved.translation.norm() > 1e-9 || moved.rotation.norm() > 1e-9;
    }
  }

  // How far the base must come down for every corrected target to be within reach of a leg whose knee keeps
  // `stance_knee`: each such leg is solved with that floor first, and where it falls short, the distance it
  // did reach from its hip is the radius of the sphere the target must come within.
  LegSolveOptions leg_options;
  leg_options.velocity_limit_scale = options.velocity_limit_scale;
  LegSolver solver(model, chains, leg_options);
  Eigen::VectorXd previous(nq);
  int64_t previous_frame = -2;
  std::vector<double> need(static_cast<size_t>(frames), 0.0);
  std::vector<Eigen::Isometry3d> frame_targets(foot_count);
  std::vector<bool> active(foot_count);
  if (vertical_coordinate >= 0) {
    for (int64_t t = 0; t < frames; ++t) {
      bool any = false;
      for (size_t f = 0; f < foot_count; ++f) {
        // Only a foot a contact (or the floor) moved asks for reach: one that merely follows the source
        // where the IK did not put it is where the capture's own leg was, and a straight leg may stay so.
        active[f] = corrected[f][static_cast<size_t>(t)];
        frame_targets[f] = target[f][static_cast<size_t>(t)];
        any = any || active[f];
      }
      if (!any) continue;
      frame_q = Eigen::Map<const Eigen::VectorXd>(&q[static_cast<size_t>(t * nq)], nq);
      ContinueLegs(chains, previous, t - 1 == previous_frame, false, frame_q);
      solver.solve(frame_targets, active, frame_q, options.stance_knee);
      previous = frame_q, previous_frame = t;
      for (size_t f = 0; f < foot_count; ++f) {
        if (!active[f]) continue;
        const Eigen::Vector3d reached = solver.reached(f).translation();
        const Eigen::Vector3d& wanted = frame_targets[f].translation();
        if ((reached - wanted).norm() < 1e-3) continue;
        const Eigen::Vector3d& hip_at = hip[f][static_cast<size_t>(t)];
        const double reach = (hip_at - reached).norm(), cap = options.max_lowering * chains[f].length;
        const Eigen::Vector3d d = hip_at - wanted;
        const double sideways = d.head<2>().squaredNorm();
        double drop = sideways < reach * reach ? d.z() - std::sqrt(reach * reach - sideways) : cap + 1.0;
        if (drop > cap) ++out.capped_lowering_frames, drop = cap;
        need[static_cast<size_t>(t)] = std::max(need[static_cast<size_t>(t)], drop);
      }
    }
  }
  const int64_t half_width = static_cast<int64_t>(std::lround(options.lowering_smoothing / std::max(dt, 1e-9)));
  const std::vector<double> lowering = SmoothUpperEnvelope(need, half_width);

  const int64_t base_half_width = static_cast<int64_t>(std::lround(options.base_smoothing / std::max(dt, 1e-9)));
  const BaseMover mover(model);
  const std::vector<Vector6d> base_correction =
      options.move_base_for_plants
          ? BaseCorrections(model, mover, tree, solver, chains, contacts, target, lowering, vertical_coordinate, base_half_width, q)
          : std::vector<Vector6d>(static_cast<size_t>(frames), Vector6d::Zero());

  out.clearance_frames = RaiseSwingFeetToClearance(solver, chains, mover, soles, contacts, clearance, lowering, base_correction,
                                                   vertical_coordinate, nq, q, time_s, clearance_half_width, target, changed);

  int64_t iterations = 0;
  std::vector<bool> retry(foot_count), planted(foot_count, false), held(foot_count, false);
  Vector6d speed_move = Vector6d::Zero();  // HoldPlantsWithinSpeed's pelvis move, carried from frame to frame
  HoldScratch hold_scratch;
  Eigen::VectorXd before_speed_move(nq);  // the frame before that move, to re-apply a changed one
  Eigen::VectorXd lift_scratch(nq);       // LowerOntoLiftedPlants' frame before a round, and its feet's misses
  FootMisses misses{std::vector<double>(foot_count), std::vector<double>(foot_count)}, lowered_misses = misses;
  // Per foot and frame, the contact phase that begins there (-1: none).
  std::vector<std::vector<int>> phase_begins(foot_count, std::vector<int>(static_cast<size_t>(frames), -1));
  for (size_t p = 0; p < contacts.phases.size(); ++p) {
    const ContactPhase& phase = contacts.phases[p];
    if (phase.foot >= 0 && static_cast<size_t>(phase.foot) < foot_count) phase_begins[static_cast<size_t>(phase.foot)][static_cast<size_t>(phase.begin)] = static_cast<int>(p);
  }

  previous_frame = -2;
  Eigen::VectorXd before(nq);  // the previous frame, final: the velocity limits' centre
  for (int64_t t = 0; t < frames; ++t) {
    if (t > 0) before = Eigen::Map<const Eigen::VectorXd>(&q[static_cast<size_t>((t - 1) * nq)], nq);
    const double step_time = t > 0 ? options.velocity_limit_scale * (time_s[static_cast<size_t>(t)] - time_s[static_cast<size_t>(t - 1)]) : 0.0;
    const double drop = lowering[static_cast<size_t>(t)];
    const Vector6d& moved = base_correction[static_cast<size_t>(t)];
    const bool base_moved = moved.squaredNorm() > 0;
    bool any = drop > 1e-9 || base_moved || speed_move.squaredNorm() > 0;
    for (size_t f = 0; f < foot_count; ++f) any = any || changed[f][static_cast<size_t>(t)];
    if (!any) continue;
    frame_q = Eigen::Map<const Eigen::VectorXd>(&q[static_cast<size_t>(t * nq)], nq);
    if (drop > 1e-9) frame_q[vertical_coordinate] -= drop;
    if (base_moved) {
      mover.apply(moved, frame_q);
      ++out.base_moved_frames;
      out.max_base_turn = std::max(out.max_base_turn, moved.head<3>().norm());
      out.max_base_shift = std::max(out.max_base_shift, moved.tail<3>().norm());
    }
    before_speed_move = frame_q;
    if (speed_move.squaredNorm() > 0) mover.apply(speed_move, frame_q);
    ContinueLegs(chains, previous, t - 1 == previous_frame, previous_frame < 0, frame_q);
    for (size_t f = 0; f < foot_count; ++f) {
      frame_targets[f] = target[f][static_cast<size_t>(t)];
      active[f] = drop > 1e-9 || base_moved || changed[f][static_cast<size_t>(t)];
      planted[f] = options.contacts_above_speed && contacts.planted(t, f);
    }
    LegSolveResult solved = solver.solve(frame_targets, active, frame_q, 0.0, &before, step_time, &planted);
    solved.iterations += BendStraightKnees(chains, solver, frame_targets, active, frame_q, before, step_time, planted, retry);
    if (options.move_base_for_plants && mover.canMove()) {
      for (size_t f = 0; f < foot_count; ++f) held[f] = active[f] && contacts.planted(t, f);
      Vector6d step;
      if (HoldPlantsWithinSpeed(mover, tree, solver, chains, frame_targets, held, before, step_time, planted, speed_move,
                                hold_scratch, frame_q, step)) {
        speed_move += step;
      } else if (speed_move.squaredNorm() > 0) {
        // Nothing to hold: the pelvis returns towards the tracking as fast as a move may change.
        step = -speed_move;
        LimitBaseStep(step);
        frame_q = before_speed_move;
        speed_move += step;
        if (speed_move.squaredNorm() > 0) mover.apply(speed_move, frame_q);
        ContinueLegs(chains, previous, t - 1 == previous_frame, previous_frame < 0, frame_q);
      }
      if (step.squaredNorm() > 0) {
        const LegSolveResult again = solver.solve(frame_targets, active, frame_q, 0.0, &before, step_time, &planted);
        solved.iterations += again.iterations;
        solved.position_error = again.position_error, solved.angle_error = again.angle_error;
      }
      if (speed_move.squaredNorm() > 0) ++out.speed_base_moved_frames;
    }
    if (vertical_coordinate >= 0) {
      solved.iterations += LowerOntoLiftedPlants(solver, soles, contacts, t, frame_targets, active, before, step_time, planted,
                                                 vertical_coordinate, frame_q, lift_scratch, misses, lowered_misses, out);
    }
    for (int round = 0; round < 5; ++round) {
      bool rolled = false;
      for (size_t f = 0; f < foot_count; ++f) {
        retry[f] = false;
        if (!active[f]) continue;
        const Eigen::Isometry3d& reached = solver.reached(f);
        const double lowest = LowestPoint(soles[f], reached);
        const bool through_floor = lowest < -kFloorTolerance;
        // A planted foot rolls onto the edge it pitches towards; any other foot is lifted by its depth (a
        // swing foot's pitch is the source's, and rolling it turned one unreachable pose into two the leg
        // then alternated between, 0.4 rad a frame on CMU 05_02).
        if (through_floor && contacts.planted(t, f)) {
          frame_targets[f] = RollAboutSoleEdge(soles[f], frame_targets[f], reached), ++out.rolled_foot_frames;
        } else if (through_floor) {
          frame_targets[f].translation().z() -= lowest;
        }
        retry[f] = through_floor;
        rolled = rolled || through_floor;
      }
      if (!rolled) break;
      const LegSolveResult again = solver.solve(frame_targets, retry, frame_q, 0.0, &before, step_time, &planted);
      solved.iterations += again.iterations;
      // The worst of either solve: a rolled foot's first error was against the flat pose it gave up.
      solved.position_error = std::max(solved.position_error, again.position_error);
      solved.angle_error = std::max(solved.angle_error, again.angle_error);
    }
    // What still leaves a sole in the floor is a leg its limits keep from the target: the ankle cannot
    // pitch the foot flat (a running stance foot), or the leg cannot move that fast (the base dropping
    // faster than a knee can bend, as where a take's first frames leave the reference stance). The foot
    // then stands on its lowest point instead: its target rises by the depth, and from the second round
    // the base rises with it (above the pelvis task, as contacts rank above every task).
    for (int round = 0; round < 3; ++round) {
      double deepest = 0.0;
      for (size_t f = 0; f < foot_count; ++f) {
        retry[f] = false;
        if (!active[f]) continue;
        const double lowest = LowestPoint(soles[f], solver.reached(f));
        if (lowest >= -kFloorTolerance) continue;
        frame_targets[f].translation().z() -= lowest;
        retry[f] = true;
        deepest = std::min(deepest, lowest);
      }
      if (deepest == 0.0) break;
      if (round == 0) ++out.lifted_frames;
      if (round > 0 && vertical_coordinate >= 0) {
        frame_q[vertical_coordinate] -= deepest;
        for (size_t f = 0; f < foot_count; ++f) retry[f] = active[f];
        if (round == 1) ++out.raised_frames;
      }
      const LegSolveResult again = solver.solve(frame_targets, retry, frame_q, 0.0, &before, step_time, &planted);
      solved.iterations += again.iterations;
    }
    iterations += solved.iterations;
    ++out.solved_frames;
    // A planted foot the legs left off its plant: its sole centre horizontally more than kOffPlant from the
    // plant's. (The roll about a sole edge at a phase's ends moves the centre under 2 mm.)
    bool off_plant = false;
    for (size_t f = 0; f < foot_count; ++f) {
      if (!active[f] || !contacts.planted(t, f)) continue;
      const Eigen::Vector3d reached = solver.reached(f) * soles[f].centre, wanted = target[f][static_cast<size_t>(t)] * soles[f].centre;
      off_plant = off_plant || (reached - wanted).head<2>().norm() > kOffPlant;
    }
    out.unreachable_frames += off_plant ? 1 : 0;
    if (drop > 1e-3) ++out.lowered_frames;
    out.max_lowering = std::max(out.max_lowering, drop);
    if (solved.position_error > out.worst_position_error) {
      out.worst_position_error = solved.position_error, out.worst_frame = t;
    }
    out.worst_angle_error = std::max(out.worst_angle_error, solved.angle_error);
    out.moved_plants += PlantWhereTouchedDown(soles, contacts, phase_begins, time_s, options.blend, solver, active, t, target, changed);
    std::copy(frame_q.data(), frame_q.data() + nq, q.begin() + t * nq);
    previous = frame_q, previous_frame = t;
  }
  out.mean_iterations = out.solved_frames ? static_cast<double>(iterations) / static_cast<double>(out.solved_frames) : 0.0;
  MeasureOverspeed(model, chains, time_s, q, out);
  MeasureLimitedStance(model, chains, contacts, q, out);
}

}  // namespace syn
