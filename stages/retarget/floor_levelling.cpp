#include "stages/retarget/floor_levelling.h"

#include <cmath>
#include <cstdio>

#include <Eigen/Cholesky>
#include <Eigen/Eigenvalues>

#include "stages/retarget/horizontal_speed.h"

namespace syn {

bool FloorLevellingOptions::IsValid(std::string* error) const {
  const auto fail = [&](const std::string& message) {
    if (error != nullptr) *error = message;
    return false;
  };
  if (!(still_speed > 0) || !(speed_window > 0)) return fail("floor levelling: still_speed and speed_window must be > 0");
  if (!(band > 0) || !(min_spread > 0) || !(max_residual > 0)) return fail("floor levelling: band, min_spread and max_residual must be > 0 (m)");
  if (!(max_tilt > 0 && max_tilt < M_PI / 2)) return fail("--level-floor-max-tilt must be in (0, 90) degrees");
  if (!(min_tilt >= 0 && min_tilt < max_tilt)) return fail("--level-floor-min-tilt must be in [0, --level-floor-max-tilt) degrees");
  if (!(min_kept > 0 && min_kept <= 1)) return fail("floor levelling: min_kept must be in (0, 1]");
  return true;
}

FloorPlane EstimateFloorPlane(const std::vector<std::vector<Eigen::Vector3d>>& foot_positions,
                              const std::vector<double>& time_s, const FloorLevellingOptions& options) {
  FloorPlane plane;
  std::vector<Eigen::Vector3d> samples;
  for (const std::vector<Eigen::Vector3d>& foot : foot_positions) {
    const std::vector<double> speed = CentredHorizontalSpeeds(foot, time_s, options.speed_window);
    for (size_t t = 0; t < foot.size(); ++t) {
      if (speed[t] < options.still_speed) samples.push_back(foot[t]);
    }
  }
  if (samples.size() < 10) {
    plane.note = "the floor was not levelled: fewer than 10 standing foot samples";
    return plane;
  }
  // Fit in coordinates centred on the samples, along the principal horizontal directions of their spread,
  // a slope only along a direction they spread over.
  Eigen::Vector2d mean = Eigen::Vector2d::Zero();
  for (const Eigen::Vector3d& s : samples) mean += s.head<2>();
  mean /= static_cast<double>(samples.size());
  Eigen::Matrix2d spread = Eigen::Matrix2d::Zero();
  for (const Eigen::Vector3d& s : samples) spread += (s.head<2>() - mean) * (s.head<2>() - mean).transpose();
  spread /= static_cast<double>(samples.size());
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d> axes(spread);
  std::vector<Eigen::Vector2d> directions;
  for (int i = 0; i < 2; ++i) {
    if (std::sqrt(std::max(axes.eigenvalues()[i], 0.0)) >= options.min_spread) directions.push_back(axes.eigenvectors().col(i));
  }
  const int columns = 1 + static_cast<int>(directions.size());
  Eigen::VectorXd row(columns);
  const auto design_row = [&](const Eigen::Vector3d& sample) -> const Eigen::VectorXd& {  // 1, then the offsets along the directions
    row[0] = 1;
    for (size_t d = 0; d < directions.size(); ++d) row[static_cast<Eigen::Index>(d + 1)] = directions[d].dot(sample.head<2>() - mean);
    return row;
  };
  std::vector<bool> kept(samples.size(), true);
  Eigen::VectorXd coefficients = Eigen::VectorXd::Zero(columns);  // height at the mean, then slopes
  // A fit, then three refits without the samples more than `band` above the last one.
  for (int round = 0; round < 4; ++round) {
    Eigen::MatrixXd normal = Eigen::MatrixXd::Zero(columns, columns);
    Eigen::VectorXd rhs = Eigen::VectorXd::Zero(columns);
    int64_t count = 0;
    for (size_t i = 0; i < samples.size(); ++i) {
      if (!kept[i]) continue;
      design_row(samples[i]);
      normal += row * row.transpose();
      rhs += row * samples[i].z();
      ++count;
    }
    if (count < 10) break;
    coefficients = normal.ldlt().solve(rhs);
    if (round == 3) break;
    for (size_t i = 0; i < samples.size(); ++i) kept[i] = samples[i].z() - design_row(samples[i]).dot(coefficients) <= options.band;
  }
  Eigen::Vector2d gradient = Eigen::Vector2d::Zero();  // dz/dx, dz/dy
  for (size_t d = 0; d < directions.size(); ++d) gradient += coefficients[static_cast<Eigen::Index>(d + 1)] * directions[d];
  double squares = 0;
  for (size_t i = 0; i < samples.size(); ++i) {
    if (!kept[i]) continue;
    const double residual = samples[i].z() - (coefficients[0] + gradient.dot(samples[i].head<2>() - mean));
    squares += residual * residual;
    ++plane.samples;
  }
  plane.residual = std::sqrt(squares / static_cast<double>(std::max<int64_t>(plane.samples, 1)));
  plane.kept_fraction = static_cast<double>(plane.samples) / static_cast<double>(samples.size());
  plane.normal = Eigen::Vector3d(-gradient.x(), -gradient.y(), 1.0).normalized();
  plane.tilt_rad = std::acos(std::clamp(plane.normal.z(), -1.0, 1.0));
  plane.centroid = Eigen::Vector3d(mean.x(), mean.y(), coefficients[0]);
  char text[256];
  if (plane.tilt_rad > options.max_tilt || plane.residual > options.max_residual || plane.kept_fraction < options.min_kept) {
    std::snprintf(text, sizeof text,
                  "the floor was not levelled: %.0f %% of its stance samples fit a plane tilted %.2f° with %.0f mm "
                  "residual (not a floor: uneven terrain or steps; levelled only up to %.1f°, %.0f mm and from %.0f %%)",
                  100 * plane.kept_fraction, plane.tilt_rad * 180 / M_PI, plane.residual * 1000, options.max_tilt * 180 / M_PI,
                  options.max_residual * 1000, 100 * options.min_kept);
    plane.note = text;
    plane.uneven = true;
    return plane;
  }
  plane.rotation = Eigen::Quaterniond::FromTwoVectors(plane.normal, Eigen::Vector3d::UnitZ());
  plane.levelled = options.enabled && plane.tilt_rad >= options.min_tilt;
  return plane;
}

void LevelLandmarks(const FloorPlane& plane, LandmarkTrajectories& landmarks) {
  if (!plane.levelled) return;
  const Eigen::Matrix3d rotation = plane.rotation.toRotationMatrix();
  for (size_t k = 0; k + 7 <= landmarks.pose.size(); k += 7) {
    double* pose = &landmarks.pose[k];
    const Eigen::Vector3d position(pose[0], pose[1], pose[2]);
    if (position.allFinite()) {
      const Eigen::Vector3d turned = plane.centroid + rotation * (position - plane.centroid);
      pose[0] = turned.x(), pose[1] = turned.y(), pose[2] = turned.z();
    }
    const Eigen::Quaterniond orientation(pose[3], pose[4], pose[5], pose[6]);
    if (orientation.coeffs().allFinite()) {
      const Eigen::Quaterniond turned = plane.rotation * orientation;
      pose[3] = turned.w(), pose[4] = turned.x(), pose[5] = turned.y(), pose[6] = turned.z();
    }
  }
}

}  // namespace syn
