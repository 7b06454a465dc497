#include "stages/retarget/trajectory_refinement.h"

#include <algorithm>
#include <cmath>

#include <stdexcept>
#include <string>

#include <Eigen/Geometry>

#include "common/configuration_space.h"
#include "stages/retarget/block_banded_system.h"
#include "stages/retarget/branch_joints.h"
#include "stages/retarget/speed_bound.h"

namespace syn {
namespace {

constexpr double kReferenceStep = 0.01;  // s: accelerations are weighted as displacements over 10 ms

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Adds one frame's linearised IK residual ‖r + J x_k‖² to the normal equations.
void AddTracking(BlockBandedSystem& system, int k, const Eigen::VectorXd& residual, const RowMatrix& jacobian) {
  system.diagonal(k).selfadjointView<Eigen::Lower>().rankUpdate(jacobian.transpose());
  system.rhs(k).noalias() -= jacobian.transpose() * residual;
}

// Adds ‖c₋ x_{k-1} + c₀ x_k + c₊ x_{k+1} + b‖² with b = c₊ d₊ − c₋ d₋: the second difference of q in
// the tangent space, d± the IK solution's own steps, weighted s σ_u (0.01 s)² · 2/(h₋ + h₊) per velocity u
// (s: `smoothing`, σ: `scale`). Its Jacobian blocks are diagonal, so it only touches diagonals.
void AddAcceleration(BlockBandedSystem& system, int k, const Eigen::VectorXd& step_before, const Eigen::VectorXd& step_after,
                     double h_before, double h_after, double smoothing, const Eigen::VectorXd& scale_per_velocity) {
  const double scale = kReferenceStep * kReferenceStep * 2.0 / (h_before + h_after);
  const double c[3] = {scale / h_before, -scale / h_after - scale / h_before, scale / h_after};
  const auto w2 = (smoothing * scale_per_velocity.array()).square();
  for (int a = 0; a < 3; ++a) {
    system.diagonal(k - 1 + a).diagonal().array() += c[a] * c[a] * w2;
    system.rhs(k - 1 + a).array() -= c[a] * w2 * (c[2] * step_after.array() - c[0] * step_before.array());
  }
  system.lower(k, 1).diagonal().array() += c[1] * c[0] * w2;
  system.lower(k + 1, 1).diagonal().array() += c[2] * c[1] * w2;
  system.lower(k + 1, 2).diagonal().array() += c[2] * c[0] * w2;
}

// q1 ⊖ q0 in the velocity space (a free base's rotation as log(R1 R0ᵀ), ground frame).
void TangentStep(const Model& model, const double* q0, const double* q1, Eigen::VectorXd& step) {
  const int nq = model.nq();
  int q = 0, u = 0;
  if (model.hasFreeBase()) {
    const Eigen::Quaterniond r0(q0[0], q0[1], q0[2], q0[3]), r1(q1[0], q1[1], q1[2], q1[3]);
    const Eigen::AngleAxisd turn((r1.normalized() * r0.normalized().conjugate()).normalized());
    step.head<3>() = turn.angle() * turn.axis();
    for (int i = 0; i < 3; ++i) step[3 + i] = q1[4 + i] - q0[4 + i];
    q = 7;
    u = 6;
  }
  for (; q < nq; ++q, ++u) step[u] = q1[q] - q0[q];
}

}  // namespace

void RefineTrajectory(FrameIk& ik, const Model& model, const std::vector<std::vector<IkTarget>>& targets,
                      const std::vector<double>& times, std::vector<double>& q, const RefinementOptions& options) {
  const int64_t frames = static_cast<int64_t>(times.size()), nq = model.nq(), nu = model.nu();
  if (options.smoothing <= 0 || frames < 3) return;
  const int first_joint = model.hasFreeBase() ? 6 : 0, q_offset = model.hasFreeBase() ? 1 : 0;
  // The IK's limits: a knee stays on the bent side of straight (branch_joints.h).
  const Eigen::VectorXd lower_limit = RetargetLowerLimits(model);
  std::vector<Eigen::VectorXd> correction(static_cast<size_t>(frames), Eigen::VectorXd::Zero(nu));
  std::vector<Eigen::VectorXd> step(static_cast<size_t>(frames), Eigen::VectorXd::Zero(nu));  // IK's own q_t ⊖ q_{t-1}
  for (int64_t t = 1; t < frames; ++t) {
    TangentStep(model, &q[static_cast<size_t>((t - 1) * nq)], &q[static_cast<size_t>(t * nq)], step[static_cast<size_t>(t)]);
  }
  // Per frame and velocity, the IK's factor on its smoothing weights (FrameIk::regularisationScales):
  // targets the IK met exactly are tracked as exactly here. 1 where a frame has no targets.
  std::vector<Eigen::VectorXd> smoothing_scale(static_cast<size_t>(frames), Eigen::VectorXd::Ones(nu));
  BlockBandedSystem system;
  std::vector<Eigen::VectorXd> solution;
  Eigen::VectorXd residual, frame_q(nq);
  RowMatrix jacobian;
  const int64_t advance = std::max(3, options.window - options.overlap);
  for (int64_t start = 0; start < frames - 2; start += advance) {
    const int64_t end = std::min(frames, start + options.window);
    const int blocks = static_cast<int>(end - start);
    system.reset(blocks, static_cast<int>(nu));
    for (int k = 0; k < blocks; ++k) {
      const size_t t = static_cast<size_t>(start + k);
      const Eigen::VectorXd& x = correction[t];
      // The first two frames of a later window keep what the previous window found: the join stays smooth.
      if (start > 0 && k < 2) {
        for (int u = 0; u < nu; ++u) system.fix(k, u, x[u]);
        continue;
      }
      frame_q = Eigen::Map<const Eigen::VectorXd>(&q[t * static_cast<size_t>(nq)], nq);
      // A joint the IK left on a limit stays there: the tracking residual would otherwise pull it through
      // (the IK held it there because the targets ask for more), and clamping afterwards would undo the
      // compensation the rest of the body made for it. The raised knee floor counts (branch_joints.h): a
      // straight knee held there tracks CMU 05_02 at 54.7 mm P1 median, let go 66.8 mm (the same-robot round
      // trip's no-enforcement knees prefer it let go: max 28-36 deg held, 10-21 deg let go).
      for (int u = first_joint; u < nu; ++u) {
        const double value = frame_q[u + q_offset];
        if (value <= lower_limit[u + q_offset] + 1e-9 || value >= model.qUpper()[u + q_offset] - 1e-9) {
          system.fix(k, u, x[u]);
        }
      }
      if (!targets[t].empty()) {
        ik.linearize(targets[t], frame_q, residual, jacobian);
        AddTracking(system, k, residual, jacobian);
        ik.regularisationScales(targets[t], frame_q, smoothing_scale[t]);
      }
    }
    for (int k = 1; k + 1 < blocks; ++k) {
      const size_t t = static_cast<size_t>(start + k);
      AddAcceleration(system, k, step[t], step[t + 1], times[t] - times[t - 1], times[t + 1] - times[t], options.smoothing,
                      smoothing_scale[t]);
    }
    if (!system.solve(solution)) {
      throw std::runtime_error("trajectory refinement: the smoothing problem of frames " + std::to_string(start) +
                               "-" + std::to_string(end - 1) + " is singular (no targets and nothing to anchor them)");
    }
    for (int k = 0; k < blocks; ++k) correction[static_cast<size_t>(start + k)] = solution[static_cast<size_t>(k)];
    if (end == frames) break;
  }
  Eigen::VectorXd refined(nq);
  const ConfigurationShape shape = ConfigurationShape::Of(model.hasFreeBase(), model.nq());
  for (int64_t t = 0; t < frames; ++t) {
    frame_q = Eigen::Map<const Eigen::VectorXd>(&q[static_cast<size_t>(t * nq)], nq);
    Integrate(shape, frame_q, correction[static_cast<size_t>(t)], refined);
    for (int u = first_joint; u < nu; ++u) {
      double lower = lower_limit[u + q_offset], upper = model.qUpper()[u + q_offset];
      // The velocity limit from the previous (already final) frame: the smoothing does not bound
      // velocities by itself, and on the fastest captures it would ask more of a motor than the IK did.
      const double reach = t > 0 ? options.velocity_limit_scale * SpeedPerScaledSecond(model.uLimit()[u], options.velocity_limit_scale) *
                                       (times[static_cast<size_t>(t)] - times[static_cast<size_t>(t - 1)])
                                 : 0.0;
      if (t > 0 && options.velocity_limit_scale > 0 && std::isfinite(reach)) {
        const double previous = q[static_cast<size_t>((t - 1) * nq + u + q_offset)];
        lower = std::max(lower, std::min(previous - reach, upper));
        upper = std::min(upper, std::max(previous + reach, lower));
      }
      refined[u + q_offset] = std::clamp(refined[u + q_offset], lower, upper);
    }
    std::copy(refined.data(), refined.data() + nq, q.begin() + t * nq);
  }
}

}  // namespace syn
