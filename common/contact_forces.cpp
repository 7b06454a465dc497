#include "common/contact_forces.h"

#include <cmath>
#include <string>

#include <Eigen/LU>

#include "common/error.h"

namespace syn {
namespace {

constexpr int kPyramidEdges = 8;

// The link that the last unactuated joint moves: for a free base its child, for a virtual chain
// (three prismatic, three revolute joints through massless links) the first massive link after it.
int FindBaseLink(const Model& model, std::vector<int>& unactuated) {
  const std::vector<bool>& actuated = model.actuatedVelocities();
  for (int v = 0; v < model.nu(); ++v) {
    if (!actuated[static_cast<size_t>(v)]) unactuated.push_back(v);
  }
  if (unactuated.empty()) return -1;
  int last_u = -1;
  std::string child;
  for (const ModelJoint& joint : model.joints()) {
    if (joint.u_index >= 0 && !actuated[static_cast<size_t>(joint.u_index)] && joint.u_index > last_u) {
      last_u = joint.u_index, child = joint.child;
    }
  }
  return model.findLinkIndex(child);
}

// One column per friction-pyramid edge of every sole point: the most a frame can have in contact.
int MaxColumns(const std::vector<RobotFoot>& feet) {
  size_t points = 0;
  for (const RobotFoot& foot : feet) points += foot.sole_points.size();
  return static_cast<int>(points) * kPyramidEdges;
}

}  // namespace

bool ContactForceOptions::IsValid(std::string* error) const {
  if (!(friction > 0)) return *error = "--friction must be > 0", false;
  if (!(max_height >= 0)) return *error = "the contact force height must be >= 0", false;
  if (!(max_speed >= 0)) return *error = "the contact force speed must be >= 0", false;
  return true;
}

ContactForceSplit::ContactForceSplit(const Model& model, const std::vector<RobotFoot>& feet,
                                     const ContactForceOptions& options)
    : feet_(feet), options_(options), nonnegative_fit_(MaxColumns(feet)), least_norm_(MaxColumns(feet)) {
  for (const RobotFoot& foot : feet_) point_count_ += foot.sole_points.size();
  base_link_ = FindBaseLink(model, unactuated_);
  if (base_link_ < 0) return;
  if (unactuated_.size() != 6) {
    throw DataError(Location::InFile(model.sourcePath()),
                    "the model has " + std::to_string(unactuated_.size()) +
                        " unactuated velocities; splitting the base's residual into contact forces needs six");
  }
  for (const RobotFoot& foot : feet_) foot_links_.push_back(model.findLinkIndex(foot.link));
  for (int k = 0; k < kPyramidEdges; ++k) {
    const double angle = 2 * M_PI * k / kPyramidEdges;
    edges_.emplace_back(options_.friction * std::cos(angle), options_.friction * std::sin(angle), 1.0);
  }
  const int max_columns = MaxColumns(feet_);
  jacobian_.resize(6, model.nu());
  columns_.resize(6, max_columns);
  weighted_columns_.resize(6, max_columns);
  column_foot_.resize(static_cast<size_t>(max_columns));
  column_point_.resize(static_cast<size_t>(max_columns));
  weights_.resize(max_columns);
}

Eigen::Matrix<double, 6, 6> ContactForceSplit::baseJacobianAtCentre(Workspace& workspace) {
  const Eigen::Vector3d centre = workspace.findCenterOfMass();
  const Eigen::Isometry3d base_pose = workspace.findLinkPose(base_link_);
  workspace.calcFrameJacobian(base_link_, base_pose.inverse() * centre, jacobian_);
  Eigen::Matrix<double, 6, 6> base_jacobian;
  for (int k = 0; k < 6; ++k) base_jacobian.col(k) = jacobian_.col(unactuated_[static_cast<size_t>(k)]);
  return base_jacobian;
}

Eigen::Matrix<double, 6, 6> ContactForceSplit::wrenchFromBaseForces(Workspace& workspace) {
  if (base_link_ < 0) return Eigen::Matrix<double, 6, 6>::Zero();
  return baseJacobianAtCentre(workspace).transpose().partialPivLu().inverse();
}

void ContactForceSplit::split(Workspace& workspace, const Eigen::VectorXd& u, const Eigen::VectorXd& tau, const int64_t* planted,
                              ContactForceFrame& out) {
  Eigen::Matrix<double, 6, 1> wanted = Eigen::Matrix<double, 6, 1>::Zero();
  if (base_link_ >= 0) {
    Eigen::Matrix<double, 6, 1> base_tau;
    for (int k = 0; k < 6; ++k) base_tau(k) = tau(unactuated_[static_cast<size_t>(k)]);
    wanted = baseJacobianAtCentre(workspace).transpose().partialPivLu().solve(base_tau);
  }
  fit(workspace, u, wanted, planted, out);
}

void ContactForceSplit::fit(Workspace& workspace, const Eigen::VectorXd& u, const Eigen::Matrix<double, 6, 1>& wanted,
                            const int64_t* planted, ContactForceFrame& out, const Eigen::Matrix<double, 6, 1>& row_weights) {
  out.foot_force.resize(feet_.size());
  for (Eigen::Vector3d& force : out.foot_force) force.setZero();
  out.point_force.resize(point_count_);
  for (Eigen::Vector3d& force : out.point_force) force.setZero();
  out.residual.setZero();
  out.unexplained.setZero();
  if (base_link_ < 0) return;
  out.residual = wanted;
  const Eigen::Vector3d centre = workspace.findCenterOfMass();

  int n = 0, point_number = 0;
  for (size_t f = 0; f < feet_.size(); ++f) {
    const Eigen::Isometry3d foot_pose = workspace.findLinkPose(foot_links_[f]);
    bool twist_known = false;  // an unplanted foot's velocity, computed once one of its points is down
    for (const std::array<double, 3>& local : feet_[f].sole_points) {
      const int this_point = point_number++;
      const Eigen::Vector3d point = foot_pose * Eigen::Vector3d(local[0], local[1], local[2]);
      if (point.z() > options_.max_height) continue;
      if (!planted[f]) {
        if (!twist_known) {
          workspace.calcFrameJacobian(foot_links_[f], Eigen::Vector3d::Zero(), jacobian_);
          foot_twist_.noalias() = jacobian_ * u;
          twist_known = true;
        }
        const Eigen::Vector3d velocity = foot_twist_.tail<3>() + foot_twist_.head<3>().cross(point - foot_pose.translation());
        if (velocity.head<2>().norm() > options_.max_speed) continue;
      }
      const Eigen::Vector3d arm = point - centre;
      for (const Eigen::Vector3d& edge : edges_) {
        columns_.col(n).head<3>() = arm.cross(edge);
        columns_.col(n).tail<3>() = edge;
        column_foot_[static_cast<size_t>(n)] = static_cast<int>(f);
        column_point_[static_cast<size_t>(n)] = this_point;
        ++n;
      }
    }
  }
  // The fit decides what the soles explain (unique: the projection onto their cone); among the splits
  // that explain it, the least-norm one, so that each foot's share is unique and continuous in time.
  // Weighted rows scale the fit's error per component; the least-norm step keeps the fitted wrench, which
  // scaling rows does not change.
  weighted_columns_.leftCols(n).noalias() = row_weights.asDiagonal() * columns_.leftCols(n);
  nonnegative_fit_.solve(weighted_columns_.leftCols(n), row_weights.cwiseProduct(out.residual), weights_.head(n));
  least_norm_.solve(weighted_columns_.leftCols(n), weights_.head(n));
  out.unexplained = out.residual - columns_.leftCols(n) * weights_.head(n);
  for (int c = 0; c < n; ++c) {
    out.foot_force[static_cast<size_t>(column_foot_[static_cast<size_t>(c)])] += weights_(c) * columns_.col(c).tail<3>();
    out.point_force[static_cast<size_t>(column_point_[static_cast<size_t>(c)])] += weights_(c) * columns_.col(c).tail<3>();
  }
}

}  // namespace syn
