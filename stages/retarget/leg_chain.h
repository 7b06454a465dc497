// A foot's leg as a kinematic chain, and the inverse kinematics that puts the
// foot at a pose with the rest of the robot held still.
//
// The chain is every actuated one-degree-of-freedom joint on the path from the
// foot link up to the floating base (the first unactuated joint, or the root):
// six joints on G1, H1 and HRP-4C, so a reachable foot pose has an exact
// answer. The solver is damped Gauss-Newton on the foot link's 6-D pose error
// with the URDF limits clamped after each step, warm-started from the joints
// it is given: on a leg kept away from full extension that keeps the knee on
// the side it started on. Its iterations compute the foot pose and Jacobian
// from the chain's own joint frames (a product of at most a dozen transforms)
// instead of realising the whole Simbody state: Debian's Simbody runs its
// checks on every setQ, which made a leg solve cost 100 µs per iteration.
#pragma once

#include <string>
#include <vector>

#include <Eigen/Core>
#include <Eigen/Geometry>

#include "common/model.h"
#include "common/tree_kinematics.h"

namespace syn {

// One joint on the path from the leg's root link down to the foot, fixed joints included.
struct ChainJoint {
  Eigen::Isometry3d origin = Eigen::Isometry3d::Identity();  // joint frame in the parent link frame
  Eigen::Vector3d axis = Eigen::Vector3d::UnitX();           // in the joint frame
  int chain_index = -1;                                      // into LegChain::q_index; -1: fixed
  bool prismatic = false;
};

struct LegChain {
  int foot_link = -1;
  int root_link = -1;                  // the link the leg hangs from: its top joint's parent, unmoved by the leg
  int hip_link = -1;                   // child link of the chain's top joint: its origin is the hip centre
  std::vector<int> q_index, u_index;   // the chain's joints, foot first
  std::vector<double> lower, upper;    // limits per joint: the URDF's, a branch joint's lower one raised to 0
  std::vector<bool> branch;           // branch_joints.h: kept >= 0, a solve near 0 starts from kBranchStart
  std::vector<double> speed_limit;     // the URDF's velocity limit per joint (rad/s or m/s; +inf where none)
  double length = 0.0;                 // hip-to-foot-origin distance in the model's default (zero) pose
  std::vector<ChainJoint> path;        // root link to foot link

  size_t size() const { return q_index.size(); }
};

// Throws DataError naming `map_file` when the link is not a chain of one-dof joints below the base.
[[nodiscard]] LegChain FindLegChain(const Model& model, Workspace& workspace, const std::string& foot_link,
                                    const std::string& map_file);

inline constexpr int kMaxLegJoints = 8;

struct LegSolveOptions {
  int max_iterations = 30;
  double position_tolerance = 1e-6;  // m: a thousandth of a millimetre
  double angle_tolerance = 1e-5;     // rad
  double damping = 1e-4;             // initial Levenberg–Marquardt damping
  double angle_scale = 0.1;          // m per rad: how angle errors weigh against position errors
  double max_step = 0.3;             // rad per iteration and joint: keeps an early step on its branch
  double velocity_limit_scale = 1.0; // what solve()'s dt is scaled by (speed_bound.h)
};

struct LegSolveResult {
  int iterations = 0;           // summed over the solved chains
  double position_error = 0.0;  // m, the largest over the solved chains, after the last step
  double angle_error = 0.0;     // rad
};

// Solves the chains whose `active` entry is set, each for its foot link's ground-frame `targets` entry,
// changing only their joints in q: Levenberg–Marquardt on the foot's 6-D pose error (a step that does not
// lower the error is undone and the damping raised), so an unreachable target ends at the nearest pose
// the leg reaches instead of wandering. `branch_floor` is the branch joints' lower bound for this solve
// (0, or a flexion to keep).
class LegSolver {
 public:
  // `model`: the robot the chains are on (FindLegChain's).
  LegSolver(const Model& model, std::vector<LegChain> chains, const LegSolveOptions& options = {});

  // The legs' root links are placed at q by the model's own forward kinematics (tree_kinematics.h).
  // `previous` (nq, or null) with `dt` > 0: each joint stays within its velocity limit × dt of its value there,
  // the bound the per-frame IK and the refinement keep (a leg that cannot follow its foot that fast falls
  // short instead of jumping to another branch). `unbounded` (one entry per chain, or null): chains solved
  // without that bound, their position limits kept.
  LegSolveResult solve(const std::vector<Eigen::Isometry3d>& targets,
                       const std::vector<bool>& active, Eigen::VectorXd& q, double branch_floor = 0.0,
                       const Eigen::VectorXd* previous = nullptr, double dt = 0.0,
                       const std::vector<bool>* unbounded = nullptr);

  // solve with each chain's root-link pose given (`roots`, one per chain) instead of placed at q: for a caller that moves the base many times per frame (contact_enforcement's base correction).
  LegSolveResult solveFromRoots(const std::vector<Eigen::Isometry3d>& roots, const std::vector<Eigen::Isometry3d>& targets,
                                const std::vector<bool>& active, Eigen::VectorXd& q, double branch_floor = 0.0,
                                const Eigen::VectorXd* previous = nullptr, double dt = 0.0,
                                const std::vector<bool>* unbounded = nullptr);

  // Where the last solve left chain c's foot link (ground frame): valid for the chains that solve had active.
  const Eigen::Isometry3d& reached(size_t c) const { return reached_[c]; }
  // Restores what reached(c) says after a solve whose answer the caller discarded.
  void keepReached(size_t c, const Eigen::Isometry3d& pose) { reached_[c] = pose; }

  using ChainJacobian = Eigen::Matrix<double, 6, Eigen::Dynamic, 0, 6, kMaxLegJoints>;

  // Chain c's foot Jacobian at the last solve's answer (rows as its pose error: angle_scale × angular, then
  // linear; one column per chain joint, foot first), with the columns of the joints that solve left on a
  // bound (position, branch or speed) zeroed: the directions in which the leg can still follow its foot.
  // What a caller moving the leg's root needs to know how much of that move the leg takes back.
  const ChainJacobian& freeJacobian(size_t c) const { return free_jacobian_[c]; }

  double angleScale() const { return options_.angle_scale; }

  // The weighted 6-D pose error the solver minimises, (angle_scale × rotation vector, translation), and its
  // squared norm.
  double poseError(const Eigen::Isometry3d& target, const Eigen::Isometry3d& pose, Eigen::Matrix<double, 6, 1>& error) const;

 private:
  using ChainMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMaxLegJoints, kMaxLegJoints>;
  using ChainVector = Eigen::Matrix<double, Eigen::Dynamic, 1, 0, kMaxLegJoints, 1>;

  // Chain c's foot pose at q from its root link's pose, and (when `jacobian`) the foot origin's 6 × n
  // Jacobian in the chain's joints, rows (angular, linear) with the angular ones scaled by angle_scale.
  Eigen::Isometry3d footPose(size_t c, const Eigen::Isometry3d& root, const Eigen::VectorXd& q, ChainJacobian* jacobian) const;
  std::vector<LegChain> chains_;
  LegSolveOptions options_;
  std::vector<Eigen::Isometry3d> reached_;
  std::vector<ChainJacobian> free_jacobian_;
  std::vector<Eigen::Isometry3d> roots_;  // solve's root-link poses
  TreeKinematics tree_;                   // places them
  // The joints' world frames during footPose (fixed capacity: no allocation per solve).
  mutable std::vector<Eigen::Vector3d> joint_axis_, joint_position_;
  std::vector<double> saved_, lower_, upper_;  // per chain joint, for the solve under way
};

}  // namespace syn
