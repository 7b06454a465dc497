#include "stages/retarget/leg_chain.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>

#include "common/error.h"
#include "stages/retarget/branch_joints.h"

namespace syn {
namespace {

// The rotation vector (axis × angle, ground frame) that turns `from` into `to`.
Eigen::Vector3d RotationError(const Eigen::Matrix3d& to, const Eigen::Matrix3d& from) {
  const Eigen::AngleAxisd error(to * from.transpose());
  return error.axis() * error.angle();
}

}  // namespace

LegChain FindLegChain(const Model& model, Workspace& workspace, const std::string& foot_link,
                      const std::string& map_file) {
  LegChain chain;
  chain.foot_link = model.findLinkIndex(foot_link);
  if (chain.foot_link < 0) throw DataError(Location::InFile(map_file), "foot link " + foot_link + " is not in the model");
  const std::vector<ModelJoint>& joints = model.joints();
  const std::vector<bool>& actuated = model.actuatedVelocities();
  const Eigen::VectorXd retarget_lower = RetargetLowerLimits(model);
  const std::vector<bool> branch = BranchCoordinates(model);
  std::string link = foot_link;
  std::string top_child;
  // Up from the foot: fixed joints are passed through, actuated one-dof joints collected, and the first
  // unactuated joint (the floating base, real or virtual) ends the leg.
  for (size_t guard = 0; guard <= joints.size(); ++guard) {
    const auto joint = std::find_if(joints.begin(), joints.end(), [&](const ModelJoint& j) { return j.child == link; });
    if (joint == joints.end()) break;  // the root link
    if (joint->type != "fixed") {
      if (joint->u_index < 0 || !actuated[static_cast<size_t>(joint->u_index)]) break;
      if (joint->type != "revolute" && joint->type != "continuous" && joint->type != "prismatic") {
        throw DataError(Location::InFile(map_file), "the leg of " + foot_link + " has a " + joint->type +
                                                        " joint (" + joint->name + "): only one-dof joints can be solved");
      }
      chain.q_index.push_back(joint->q_index);
      chain.u_index.push_back(joint->u_index);
      chain.lower.push_back(retarget_lower[joint->q_index]);
      chain.upper.push_back(model.qUpper()[joint->q_index]);
      chain.branch.push_back(branch[static_cast<size_t>(joint->q_index)]);
      top_child = joint->child;
    }
    link = joint->parent;
  }
  if (chain.q_index.size() > static_cast<size_t>(kMaxLegJoints)) {
    throw DataError(Location::InFile(map_file), "the leg of " + foot_link + " has " + std::to_string(chain.q_index.size()) +
                                                    " actuated joints; at most " + std::to_string(kMaxLegJoints) + " are solved");
  }
  if (chain.q_index.empty()) {
    throw DataError(Location::InFile(map_file), "foot link " + foot_link + " has no actuated joint above it");
  }
  chain.hip_link = model.findLinkIndex(top_child);
  workspace.setQ(model.defaultQ());
  chain.length = (workspace.findLinkPose(chain.hip_link).translation() -
                  workspace.findLinkPose(chain.foot_link).translation()).norm();
  return chain;
}

LegSolver::LegSolver(const Model& model, std::vector<LegChain> chains, const LegSolveOptions& options)
    : chains_(std::move(chains)), options_(options), jacobian_(6, model.nu()) {
  size_t widest = 0;
  for (const LegChain& chain : chains_) widest = std::max(widest, chain.size());
  chain_jacobian_.resize(6, static_cast<Eigen::Index>(widest));
  saved_.resize(widest);
}

double LegSolver::chainError(const Workspace& workspace, size_t chain, const Eigen::Isometry3d& target,
                             Eigen::Matrix<double, 6, 1>& error) const {
  const Eigen::Isometry3d pose = workspace.findLinkPose(chains_[chain].foot_link);
  error.head<3>() = options_.angle_scale * RotationError(target.linear(), pose.linear());
  error.tail<3>() = target.translation() - pose.translation();
  return error.squaredNorm();
}

LegSolveResult LegSolver::solve(Workspace& workspace, const std::vector<Eigen::Isometry3d>& targets,
                                const std::vector<bool>& active, Eigen::VectorXd& q, double branch_floor) {
  LegSolveResult result;
  Eigen::Matrix<double, 6, 1> error, trial_error;
  ChainMatrix normal;
  ChainVector gradient, step;
  for (size_t c = 0; c < chains_.size(); ++c) {
    if (!active[c]) continue;
    const LegChain& chain = chains_[c];
    const Eigen::Index n = static_cast<Eigen::Index>(chain.size());
    const auto lower_of = [&](size_t k) { return chain.branch[k] ? std::max(chain.lower[k], branch_floor) : chain.lower[k]; };
    for (size_t k = 0; k < chain.size(); ++k) {
      double& joint = q[chain.q_index[k]];
      // A branch joint that starts below its floor (the IK's knee on the mirrored side) starts bent instead;
      // one on the floor is a straight leg carried over from the previous frame and stays where it is, or a
      // straight-legged frame would restart bent and land on another of the poses equally near an
      // unreachable target (0 <-> 0.46 rad a frame on CMU 05_02).
      if (chain.branch[k] && joint < lower_of(k)) joint = lower_of(k) + kBranchStart;
      joint = std::clamp(joint, lower_of(k), chain.upper[k]);
    }
    workspace.setQ(q);
    double cost = chainError(workspace, c, targets[c], error);
    double damping = options_.damping;
    int iteration = 0;
    for (; iteration < options_.max_iterations; ++iteration) {
      if (error.tail<3>().norm() < options_.position_tolerance &&
          error.head<3>().norm() < options_.angle_tolerance * options_.angle_scale) {
        break;
      }
      workspace.calcFrameJacobian(chain.foot_link, Eigen::Vector3d::Zero(), jacobian_);
      for (Eigen::Index j = 0; j < n; ++j) {
        chain_jacobian_.col(j).head<3>() = options_.angle_scale * jacobian_.col(chain.u_index[static_cast<size_t>(j)]).head<3>();
        chain_jacobian_.col(j).tail<3>() = jacobian_.col(chain.u_index[static_cast<size_t>(j)]).tail<3>();
      }
      // Gauss-Newton on ‖e − J δ‖², Levenberg-damped: (JᵀJ + λ I) δ = Jᵀe, with λ raised until a step lowers
      // the error.
      normal.noalias() = chain_jacobian_.leftCols(n).transpose() * chain_jacobian_.leftCols(n);
      gradient.noalias() = chain_jacobian_.leftCols(n).transpose() * error;
      bool improved = false;
      for (int attempt = 0; attempt < 8 && !improved; ++attempt) {
        ChainMatrix damped = normal;
        damped.diagonal().array() += damping;
        step = damped.ldlt().solve(gradient);
        for (Eigen::Index j = 0; j < n; ++j) {
          const size_t k = static_cast<size_t>(j);
          saved_[k] = q[chain.q_index[k]];
          q[chain.q_index[k]] = std::clamp(saved_[k] + std::clamp(step[j], -options_.max_step, options_.max_step),
                                           lower_of(k), chain.upper[k]);
        }
        workspace.setQ(q);
        const double trial_cost = chainError(workspace, c, targets[c], trial_error);
        if (trial_cost < cost) {
          improved = true;
          cost = trial_cost;
          error = trial_error;
          damping = std::max(damping / 3.0, 1e-12);
        } else {
          for (size_t k = 0; k < chain.size(); ++k) q[chain.q_index[k]] = saved_[k];
          damping *= 10.0;
        }
      }
      if (!improved) {
        workspace.setQ(q);  // back where the last accepted step left it
        break;
      }
    }
    result.iterations += iteration;
    result.position_error = std::max(result.position_error, error.tail<3>().norm());
    result.angle_error = std::max(result.angle_error, error.head<3>().norm() / options_.angle_scale);
  }
  return result;
}

}  // namespace syn
