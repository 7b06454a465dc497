#include "common/motion_from_trajectory.h"

#include <algorithm>

#include "common/row_major.h"

namespace syn {

MotionData MotionFromTrajectory(const Model& model, const std::vector<double>& times, const Eigen::MatrixXd& q,
                                const Eigen::MatrixXd& u) {
  MotionData motion;
  motion.time_s = times;
  motion.coordinate_names = model.coordinateNames();
  motion.velocity_names = model.velocityNames();
  motion.model_name = model.name();
  motion.model_sha256 = model.sourceSha256();
  motion.total_mass = model.totalMass();
  motion.q = RowMajorValues(q);
  motion.u = RowMajorValues(u);
  const Eigen::Index frames = q.rows(), nu = u.cols();
  Eigen::MatrixXd udot(frames, nu);
  for (Eigen::Index i = 0; i < frames; ++i) {
    const Eigen::Index a = std::max<Eigen::Index>(0, i - 1), b = std::min(frames - 1, i + 1);
    if (b > a) {
      udot.row(i) = (u.row(b) - u.row(a)) / (times[static_cast<size_t>(b)] - times[static_cast<size_t>(a)]);
    } else {
      udot.row(i).setZero();
    }
  }
  motion.udot = RowMajorValues(udot);
  Workspace workspace(model);
  Eigen::VectorXd qi(model.nq()), ui(nu), ai(nu), tau(nu);
  motion.tau.resize(static_cast<size_t>(frames * nu));
  for (Eigen::Index i = 0; i < frames; ++i) {
    qi = q.row(i).transpose();
    ui = u.row(i).transpose();
    ai = udot.row(i).transpose();
    workspace.setQ(qi);
    workspace.setU(ui);
    workspace.calcInverseDynamics(ai, tau);
    std::copy(tau.data(), tau.data() + nu, motion.tau.begin() + i * nu);
  }
  return motion;
}

}  // namespace syn
