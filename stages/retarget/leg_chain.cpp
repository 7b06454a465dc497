#include "stages/retarget/leg_chain.h"

#include <algorithm>
#include <cmath>

#include <Eigen/Cholesky>

#include "common/error.h"
#include "stages/retarget/branch_joints.h"
#include "stages/retarget/speed_bound.h"

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
  std::string top_child, top_parent;
  std::vector<const ModelJoint*> walked;  // foot upwards, fixed joints included
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
      chain.speed_limit.push_back(model.uLimit()[joint->u_index]);
      top_child = joint->child;
      top_parent = joint->parent;
    }
    walked.push_back(&*joint);
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
  chain.root_link = model.findLinkIndex(top_parent);
  // The path from the root link down: the walk's joints up to the top actuated one (fixed joints above it
  // belong to the body the leg hangs from), reversed.
  while (!walked.empty() && walked.back()->parent != top_parent) walked.pop_back();
  int actuated_seen = 0;
  for (auto joint = walked.rbegin(); joint != walked.rend(); ++joint) {
    ChainJoint step;
    step.origin = (*joint)->origin;
    step.axis = (*joint)->axis.normalized();
    if ((*joint)->type != "fixed") {
      // q_index runs foot first; the path runs root first.
      step.chain_index = static_cast<int>(chain.q_index.size()) - 1 - actuated_seen++;
      step.prismatic = (*joint)->type == "prismatic";
    }
    chain.path.push_back(step);
  }
  workspace.setQ(model.defaultQ());
  chain.length = (workspace.findLinkPose(chain.hip_link).translation() -
                  workspace.findLinkPose(chain.foot_link).translation()).norm();
  return chain;
}

LegSolver::LegSolver(const Model& model, std::vector<LegChain> chains, const LegSolveOptions& options)
    : chains_(std::move(chains)),
      options_(options),
      reached_(chains_.size(), Eigen::Isometry3d::Identity()),
      free_jacobian_(chains_.size()),
      roots_(chains_.size(), Eigen::Isometry3d::Identity()),
      tree_(model) {
  size_t widest = 0, longest = 0;
  for (const LegChain& chain : chains_) widest = std::max(widest, chain.size()), longest = std::max(longest, chain.path.size());
  saved_.resize(widest);
  lower_.resize(widest);
  upper_.resize(widest);
  joint_axis_.resize(longest);
  joint_position_.resize(longest);
}

Eigen::Isometry3d LegSolver::footPose(size_t c, const Eigen::Isometry3d& root, const Eigen::VectorXd& q,
                                      ChainJacobian* jacobian) const {
  const LegChain& chain = chains_[c];
  Eigen::Isometry3d pose = root;
  for (size_t j = 0; j < chain.path.size(); ++j) {
    const ChainJoint& joint = chain.path[j];
    pose = pose * joint.origin;
    if (joint.chain_index < 0) continue;
    const double value = q[chain.q_index[static_cast<size_t>(joint.chain_index)]];
    joint_axis_[j] = pose.linear() * joint.axis;
    joint_position_[j] = pose.translation();
    if (joint.prismatic) {
      pose.translation() += value * joint_axis_[j];
    } else {
      pose.linear() = pose.linear() * Eigen::AngleAxisd(value, joint.axis).toRotationMatrix();
    }
  }
  if (jacobian) {
    jacobian->resize(6, static_cast<Eigen::Index>(chain.size()));
    for (size_t j = 0; j < chain.path.size(); ++j) {
      const ChainJoint& joint = chain.path[j];
      if (joint.chain_index < 0) continue;
      const Eigen::Vector3d& axis = joint_axis_[j];
      if (joint.prismatic) {
        jacobian->col(joint.chain_index) << Eigen::Vector3d::Zero(), axis;
      } else {
        jacobian->col(joint.chain_index) << options_.angle_scale * axis, axis.cross(pose.translation() - joint_position_[j]);
      }
    }
  }
  return pose;
}

double LegSolver::poseError(const Eigen::Isometry3d& target, const Eigen::Isometry3d& pose,
                            Eigen::Matrix<double, 6, 1>& error) const {
  error.head<3>() = options_.angle_scale * RotationError(target.linear(), pose.linear());
  error.tail<3>() = target.translation() - pose.translation();
  return error.squaredNorm();
}

LegSolveResult LegSolver::solve(const std::vector<Eigen::Isometry3d>& targets,
                                const std::vector<bool>& active, Eigen::VectorXd& q, double branch_floor,
                                const Eigen::VectorXd* previous, double dt, const std::vector<bool>* unbounded) {
  // The roots from the tree's own forward kinematics: a Simbody setQ (with Debian's state checks) per
  // solve was a twentieth of the stage on CMU dances, where each frame's legs are solved several times.
  tree_.setQ(q);
  for (size_t c = 0; c < chains_.size(); ++c) {
    if (active[c]) roots_[c] = tree_.linkPose(chains_[c].root_link);
  }
  return solveFromRoots(roots_, targets, active, q, branch_floor, previous, dt, unbounded);
}

// m²/rad: a joint whose pull (Jᵀe) is below this cannot lower the error further (a hundredth of a micrometre
// of foot error over half a metre of lever).
constexpr double kStuckGradient = 1e-9;

LegSolveResult LegSolver::solveFromRoots(const std::vector<Eigen::Isometry3d>& roots,
                                         const std::vector<Eigen::Isometry3d>& targets, const std::vector<bool>& active,
                                         Eigen::VectorXd& q, double branch_floor, const Eigen::VectorXd* previous,
                                         double dt, const std::vector<bool>* unbounded) {
  LegSolveResult result;
  Eigen::Matrix<double, 6, 1> error, trial_error;
  ChainMatrix normal, damped;
  ChainVector gradient, step;
  ChainJacobian jacobian, trial_jacobian;
  for (size_t c = 0; c < chains_.size(); ++c) {
    if (!active[c]) continue;
    const LegChain& chain = chains_[c];
    const Eigen::Isometry3d& root = roots[c];
    const Eigen::Index n = static_cast<Eigen::Index>(chain.size());
    const bool speed_bound = previous && dt > 0 && !(unbounded && (*unbounded)[c]);
    for (size_t k = 0; k < chain.size(); ++k) {
      lower_[k] = chain.branch[k] ? std::max(chain.lower[k], branch_floor) : chain.lower[k];
      upper_[k] = chain.upper[k];
      double& joint = q[chain.q_index[k]];
      // A branch joint that starts below its floor (the IK's knee on the mirrored side) starts bent instead;
      // one on the floor is a straight leg carried over from the previous frame and stays where it is, or a
      // straight-legged frame would restart bent and land on another of the poses equally near an
      // unreachable target (0 <-> 0.46 rad a frame on CMU 05_02).
      if (chain.branch[k] && joint < lower_[k]) joint = lower_[k] + kBranchStart;
      const double reach = SpeedPerScaledSecond(chain.speed_limit[k], options_.velocity_limit_scale) * dt;
      if (speed_bound && std::isfinite(reach)) {
        // As the refinement's clamp: a previous value outside the limits still leaves a non-empty box.
        const double before = (*previous)[chain.q_index[k]];
        lower_[k] = std::max(lower_[k], std::min(before - reach, upper_[k]));
        upper_[k] = std::min(upper_[k], std::max(before + reach, lower_[k]));
      }
      joint = std::clamp(joint, lower_[k], upper_[k]);
    }
    Eigen::Isometry3d pose = footPose(c, root, q, &jacobian);
    double cost = poseError(targets[c], pose, error);
    double damping = options_.damping;
    int iteration = 0;
    for (; iteration < options_.max_iterations; ++iteration) {
      if (error.tail<3>().norm() < options_.position_tolerance &&
          error.head<3>().norm() < options_.angle_tolerance * options_.angle_scale) {
        break;
      }
      // Gauss-Newton on ‖e − J δ‖², Levenberg-damped: (JᵀJ + λ I) δ = Jᵀe, with λ raised until a step lowers
      // the error.
      // lazyProduct: at most 8 × 8, where Eigen's general matrix product costs more to set up than to run.
      normal.noalias() = jacobian.transpose().lazyProduct(jacobian);
      gradient.noalias() = jacobian.transpose().lazyProduct(error);
      // Converged onto the limits: every joint that could lower the error is on the bound it would cross (an
      // unreachable target's nearest pose). No step can improve, so the damping search below would only
      // fail 8 times over.
      bool can_move = false;
      for (Eigen::Index j = 0; j < n && !can_move; ++j) {
        const size_t k = static_cast<size_t>(j);
        const double joint = q[chain.q_index[k]];
        can_move = (gradient[j] > kStuckGradient && joint < upper_[k]) || (gradient[j] < -kStuckGradient && joint > lower_[k]);
      }
      if (!can_move) break;
      bool improved = false;
      for (int attempt = 0; attempt < 8 && !improved; ++attempt) {
        damped = normal;
        damped.diagonal().array() += damping;
        step = damped.llt().solve(gradient);  // positive definite: JᵀJ plus a positive damping
        for (Eigen::Index j = 0; j < n; ++j) {
          const size_t k = static_cast<size_t>(j);
          saved_[k] = q[chain.q_index[k]];
          q[chain.q_index[k]] = std::clamp(saved_[k] + std::clamp(step[j], -options_.max_step, options_.max_step),
                                           lower_[k], upper_[k]);
        }
        const Eigen::Isometry3d trial = footPose(c, root, q, &trial_jacobian);
        const double trial_cost = poseError(targets[c], trial, trial_error);
        if (trial_cost < cost) {
          improved = true;
          cost = trial_cost;
          error = trial_error;
          pose = trial;
          jacobian = trial_jacobian;
          damping = std::max(damping / 3.0, 1e-12);
        } else {
          for (size_t k = 0; k < chain.size(); ++k) q[chain.q_index[k]] = saved_[k];
          damping *= 10.0;
        }
      }
      if (!improved) break;
    }
    reached_[c] = pose;
    free_jacobian_[c] = jacobian;
    for (Eigen::Index j = 0; j < n; ++j) {
      const size_t k = static_cast<size_t>(j);
      const double joint = q[chain.q_index[k]];
      if (joint <= lower_[k] || joint >= upper_[k]) free_jacobian_[c].col(j).setZero();
    }
    result.iterations += iteration;
    result.position_error = std::max(result.position_error, error.tail<3>().norm());
    result.angle_error = std::max(result.angle_error, error.head<3>().norm() / options_.angle_scale);
  }
  return result;
}

}  // namespace syn
