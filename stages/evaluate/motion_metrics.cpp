#include "stages/evaluate/motion_metrics.h"

#include <cmath>
#include <stdexcept>

#include "common/cubic_spline.h"
#include "common/motion_integration.h"

namespace syn {
namespace {

// JSON has no NaN: a metric that does not apply is null.
nlohmann::json Number(double value) { return std::isfinite(value) ? nlohmann::json(value) : nlohmann::json(nullptr); }

struct Accumulator {
  double delta_p = 0, delta_ke = 0, kinetic = 0, power = 0;
  int64_t pairs = 0, frames = 0, first = -1, last = -1;

  void addFrame(int64_t index, double kinetic_energy, double frame_power) {
    if (first < 0) first = index;
    last = index;
    ++frames;
    kinetic += kinetic_energy;
    power += frame_power;
  }
  void addPair(double momentum_step, double energy_step) {
    delta_p += momentum_step;
    delta_ke += energy_step;
    ++pairs;
  }
  RangeMetrics finish(double start, double end, const std::vector<uint8_t>* sliding) const {
    RangeMetrics metrics;
    metrics.start_s = start;
    metrics.end_s = end;
    metrics.eval_frames = frames;
    if (pairs > 0) {
      metrics.mean_delta_p = delta_p / static_cast<double>(pairs);
      metrics.mean_delta_ke = delta_ke / static_cast<double>(pairs);
    }
    if (frames > 0) {
      metrics.mean_kinetic_energy = kinetic / static_cast<double>(frames);
      metrics.mean_power = power / static_cast<double>(frames);
      if (sliding) {
        int64_t count = 0;
        for (int64_t k = first; k <= last; ++k) count += (*sliding)[static_cast<size_t>(k)];
        metrics.foot_sliding_ratio = static_cast<double>(count) / static_cast<double>(frames);
      }
    }
    return metrics;
  }
};

}  // namespace

nlohmann::json RangeMetrics::ToJson() const {
  return {{"start_s", start_s},
          {"end_s", end_s},
          {"eval_frames", eval_frames},
          {"mean_delta_p", Number(mean_delta_p)},
          {"mean_delta_ke", Number(mean_delta_ke)},
          {"mean_kinetic_energy", Number(mean_kinetic_energy)},
          {"mean_power_w_per_kg", Number(mean_power)},
          {"foot_sliding_ratio", Number(foot_sliding_ratio)}};
}

MotionEvaluator::MotionEvaluator(const Model& model, std::vector<FootPoints> feet, double eval_rate,
                                 const FootSlidingOptions& sliding, MomentumOperator momentum)
    : workspace_(model), momentum_(momentum), feet_(std::move(feet)), eval_rate_(eval_rate), sliding_(sliding),
      actuated_(model.actuatedVelocities()) {}

std::vector<RangeMetrics> MotionEvaluator::evaluate(const std::vector<double>& time, const std::vector<double>& q,
                                                    const std::vector<double>& u, const std::vector<TimeRange>& ranges,
                                                    double grid_origin, RangeMetrics* whole, bool all_metrics) {
  const Model& model = workspace_.model();
  const int64_t nq = model.nq(), nu = model.nu(), frames = static_cast<int64_t>(time.size());
  if (frames < 2 || static_cast<int64_t>(q.size()) != frames * nq || static_cast<int64_t>(u.size()) != frames * nu) {
    throw std::invalid_argument("MotionEvaluator: need at least 2 frames of q [T, nq] and u [T, nu]");
  }
  std::vector<double> q_continuous = q;
  if (model.hasFreeBase()) MakeBaseQuaternionsContinuous(q_continuous, nq);
  const CubicSpline q_spline(time, std::move(q_continuous), nq);
  const CubicSpline u_spline(time, u, nu);

  const int64_t k_first = static_cast<int64_t>(std::ceil((time.front() - grid_origin) * eval_rate_ - 1e-9));
  const int64_t k_last = static_cast<int64_t>(std::floor((time.back() - grid_origin) * eval_rate_ + 1e-9));
  const int64_t eval_frames = std::max<int64_t>(0, k_last - k_first + 1);
  constexpr double kTimeTolerance = 1e-9;

  Eigen::VectorXd qk(nq), uk(nu), udot(nu), p(nu), p_before(nu), tau(nu);
  const size_t feet = all_metrics ? feet_.size() : 0;
  std::vector<std::vector<FootSample>> foot_samples(feet, std::vector<FootSample>(static_cast<size_t>(eval_frames)));
  Accumulator whole_sum;
  std::vector<double> power_by_velocity(all_metrics ? static_cast<size_t>(nu) : 0, 0.0);
  std::vector<Accumulator> range_sums(ranges.size());
  size_t range = 0;
  int64_t range_before = -1;
  double kinetic_before = 0;
  const double mass = model.totalMass();
  for (int64_t i = 0; i < eval_frames; ++i) {
    const double t = grid_origin + static_cast<double>(k_first + i) / eval_rate_;
    q_spline.evaluate(t, qk.data(), nullptr);
    u_spline.evaluate(t, uk.data(), udot.data());
    const bool simbody = momentum_ == MomentumOperator::kSimbody;
    if (simbody) {
      workspace_.setQ(qk);
      workspace_.calcMassTimes(uk, p);
    } else if (all_metrics) {
      workspace_.calcDynamicsAt(qk, uk, udot, p, tau);
    } else {
      workspace_.calcMassTimesAt(qk, uk, p);
    }
    const double kinetic = 0.5 * uk.dot(p);
    double power = RangeMetrics::kNone;
    if (all_metrics) {
      if (simbody) {
        workspace_.setU(uk);
        workspace_.calcInverseDynamics(udot, tau);
      }
      power = 0;
      for (int64_t v = 0; v < nu; ++v) {
        const double joint_power = std::abs(tau[v] * uk[v]);
        power_by_velocity[static_cast<size_t>(v)] += joint_power;
        if (actuated_[static_cast<size_t>(v)]) power += joint_power;
      }
      power /= mass;
    }
    for (size_t f = 0; f < feet; ++f) {
      const Eigen::Isometry3d pose = simbody ? workspace_.findLinkPose(feet_[f].link)
                                             : workspace_.findLinkPoseAtLastDynamics(feet_[f].link);
      FootSample& sample = foot_samples[f][static_cast<size_t>(i)];
      sample = {0, 0, std::numeric_limits<double>::infinity()};
      for (const Eigen::Vector3d& point : feet_[f].sole_points) {
        const Eigen::Vector3d world = pose * point;
        sample.x += world.x();
        sample.y += world.y();
        sample.lowest_z = std::min(sample.lowest_z, world.z());
      }
      sample.x /= static_cast<double>(feet_[f].sole_points.size());
      sample.y /= static_cast<double>(feet_[f].sole_points.size());
    }

    const double momentum_step = i > 0 ? (p - p_before).norm() : 0.0;
    const double energy_step = std::abs(kinetic - kinetic_before);
    whole_sum.addFrame(i, kinetic, power);
    if (i > 0) whole_sum.addPair(momentum_step, energy_step);
    while (range < ranges.size() && t > ranges[range].end + kTimeTolerance) ++range;
    const bool inside = range < ranges.size() && t >= ranges[range].start - kTimeTolerance;
    if (inside) {
      range_sums[range].addFrame(i, kinetic, power);
      if (range_before == static_cast<int64_t>(range)) range_sums[range].addPair(momentum_step, energy_step);
    }
    range_before = inside ? static_cast<int64_t>(range) : -1;
    p_before.swap(p);
    kinetic_before = kinetic;
  }

  const std::vector<uint8_t> sliding = FindSlidingFrames(foot_samples, 1.0 / eval_rate_, sliding_);
  const std::vector<uint8_t>* sliding_flags = feet == 0 ? nullptr : &sliding;
  if (whole) {
    *whole = whole_sum.finish(time.front(), time.back(), sliding_flags);
    for (double& value : power_by_velocity) value /= mass * static_cast<double>(std::max<int64_t>(1, eval_frames));
    whole->power_by_velocity = std::move(power_by_velocity);
  }
  std::vector<RangeMetrics> result;
  for (size_t r = 0; r < ranges.size(); ++r) {
    result.push_back(range_sums[r].finish(ranges[r].start, ranges[r].end, sliding_flags));
  }
  return result;
}

}  // namespace syn
