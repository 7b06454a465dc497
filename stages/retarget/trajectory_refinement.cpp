#include "stages/retarget/trajectory_refinement.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Geometry>
#include <Eigen/QR>
#include <ceres/ceres.h>

namespace syn {
namespace {

constexpr double kReferenceStep = 0.01;  // s: accelerations are weighted as displacements over 10 ms

using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// r + J x: one frame's IK residual, linearised at its solution. Stored compressed: with J = Q R (thin QR),
// ‖r + J x‖² = ‖Qᵀr + R x‖² + const, so Ceres sees nu rows instead of the tasks' and posture's many.
class LinearisedTracking final : public ceres::CostFunction {
 public:
  LinearisedTracking(const Eigen::VectorXd& residual, const RowMatrix& jacobian) {
    const Eigen::HouseholderQR<Eigen::MatrixXd> qr(jacobian);
    const Eigen::Index nu = jacobian.cols(), rank_rows = std::min(jacobian.rows(), nu);
    const Eigen::VectorXd rotated = qr.householderQ().transpose() * residual;
    residual_ = rotated.head(rank_rows);
    jacobian_ = qr.matrixQR().topRows(rank_rows).triangularView<Eigen::Upper>();
    set_num_residuals(static_cast<int>(residual_.size()));
    mutable_parameter_block_sizes()->push_back(static_cast<int>(jacobian_.cols()));
  }
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const Eigen::Map<const Eigen::VectorXd> x(parameters[0], jacobian_.cols());
    Eigen::Map<Eigen::VectorXd>(residuals, residual_.size()) = residual_ + jacobian_ * x;
    if (jacobians && jacobians[0]) Eigen::Map<RowMatrix>(jacobians[0], jacobian_.rows(), jacobian_.cols()) = jacobian_;
    return true;
  }

 private:
  Eigen::VectorXd residual_;
  RowMatrix jacobian_;
};

// s (0.01 s)² · ((d₊ + x₊ − x)/h₊ − (d₋ + x − x₋)/h₋) · 2/(h₋ + h₊): the second difference of q in the
// tangent space, d± the IK solution's own steps.
class Acceleration final : public ceres::CostFunction {
 public:
  Acceleration(Eigen::VectorXd step_before, Eigen::VectorXd step_after, double h_before, double h_after, double weight)
      : before_(std::move(step_before)), after_(std::move(step_after)) {
    const double scale = weight * kReferenceStep * kReferenceStep * 2.0 / (h_before + h_after);
    c_before_ = scale / h_before;
    c_after_ = scale / h_after;
    const int nu = static_cast<int>(before_.size());
    set_num_residuals(nu);
    for (int i = 0; i < 3; ++i) mutable_parameter_block_sizes()->push_back(nu);
  }
  bool Evaluate(double const* const* parameters, double* residuals, double** jacobians) const override {
    const Eigen::Index nu = before_.size();
    const Eigen::Map<const Eigen::VectorXd> x_before(parameters[0], nu), x(parameters[1], nu), x_after(parameters[2], nu);
    Eigen::Map<Eigen::VectorXd>(residuals, nu) =
        c_after_ * (after_ + x_after - x) - c_before_ * (before_ + x - x_before);
    if (jacobians) {
      const double diagonal[3] = {c_before_, -c_after_ - c_before_, c_after_};
      for (int block = 0; block < 3; ++block) {
        if (!jacobians[block]) continue;
        Eigen::Map<RowMatrix> J(jacobians[block], nu, nu);
        J.setZero();
        J.diagonal().setConstant(diagonal[block]);
      }
    }
    return true;
  }

 private:
  Eigen::VectorXd before_, after_;
  double c_before_ = 0, c_after_ = 0;
};

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
  std::vector<Eigen::VectorXd> correction(static_cast<size_t>(frames), Eigen::VectorXd::Zero(nu));
  std::vector<Eigen::VectorXd> step(static_cast<size_t>(frames), Eigen::VectorXd::Zero(nu));  // IK's own q_t ⊖ q_{t-1}
  for (int64_t t = 1; t < frames; ++t) {
    TangentStep(model, &q[static_cast<size_t>((t - 1) * nq)], &q[static_cast<size_t>(t * nq)], step[static_cast<size_t>(t)]);
  }
  ceres::Solver::Options solver;
  solver.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
  solver.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
  // The problem is linear: with an unbounded trust region the first LM step is the Gauss-Newton solution.
  // Joint limits are not Ceres bounds here: with bounds Ceres projects and line-searches, and a couple of
  // iterations no longer reach the solution, which left a step at every window's join. Joints on a limit
  // are held (below) and the corrected trajectory is clamped to the limits; clamping a continuous
  // trajectory keeps it continuous.
  solver.initial_trust_region_radius = 1e16;
  solver.max_num_iterations = 1;
  solver.logging_type = ceres::SILENT;
  solver.num_threads = 1;
  Eigen::VectorXd residual, frame_q(nq);
  RowMatrix jacobian;
  const int64_t advance = std::max(3, options.window - options.overlap);
  for (int64_t start = 0; start < frames - 2; start += advance) {
    const int64_t end = std::min(frames, start + options.window);
    ceres::Problem problem;
    for (int64_t t = start; t < end; ++t) {
      double* x = correction[static_cast<size_t>(t)].data();
      problem.AddParameterBlock(x, static_cast<int>(nu));
      frame_q = Eigen::Map<const Eigen::VectorXd>(&q[static_cast<size_t>(t * nq)], nq);
      // A joint the IK left on a limit stays there: the tracking residual would otherwise pull it through
      // (the IK held it there because the targets ask for more), and clamping afterwards would undo the
      // compensation the rest of the body made for it.
      std::vector<int> on_limit;
      for (int u = first_joint; u < nu; ++u) {
        const double value = frame_q[u + q_offset];
        if (value <= model.qLower()[u + q_offset] + 1e-9 || value >= model.qUpper()[u + q_offset] - 1e-9) on_limit.push_back(u);
      }
      if (!on_limit.empty() && static_cast<int>(on_limit.size()) < nu) {
        problem.SetManifold(x, new ceres::SubsetManifold(static_cast<int>(nu), on_limit));
      }
      const std::vector<IkTarget>& frame_targets = targets[static_cast<size_t>(t)];
      if (!frame_targets.empty()) {
        ik.linearize(frame_targets, frame_q, residual, jacobian);
        problem.AddResidualBlock(new LinearisedTracking(residual, jacobian), nullptr, x);
      }
      // The first two frames of a later window keep what the previous window found: the join stays smooth.
      if (start > 0 && t < start + 2) problem.SetParameterBlockConstant(x);
    }
    for (int64_t t = start + 1; t + 1 < end; ++t) {
      problem.AddResidualBlock(
          new Acceleration(step[static_cast<size_t>(t)], step[static_cast<size_t>(t + 1)],
                           times[static_cast<size_t>(t)] - times[static_cast<size_t>(t - 1)],
                           times[static_cast<size_t>(t + 1)] - times[static_cast<size_t>(t)], options.smoothing),
          nullptr, correction[static_cast<size_t>(t - 1)].data(), correction[static_cast<size_t>(t)].data(),
          correction[static_cast<size_t>(t + 1)].data());
    }
    ceres::Solver::Summary summary;
    ceres::Solve(solver, &problem, &summary);
    if (end == frames) break;
  }
  Eigen::VectorXd refined(nq);
  for (int64_t t = 0; t < frames; ++t) {
    frame_q = Eigen::Map<const Eigen::VectorXd>(&q[static_cast<size_t>(t * nq)], nq);
    ApplyVelocityStep(model, frame_q, correction[static_cast<size_t>(t)], refined);
    for (int u = first_joint; u < nu; ++u) {
      double lower = model.qLower()[u + q_offset], upper = model.qUpper()[u + q_offset];
      // The velocity limit from the previous (already final) frame: the smoothing does not bound
      // velocities by itself, and on the fastest captures it would ask more of a motor than the IK did.
      const double reach = t > 0 ? options.velocity_limit_scale * model.uLimit()[u] * (times[static_cast<size_t>(t)] - times[static_cast<size_t>(t - 1)]) : 0.0;
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
