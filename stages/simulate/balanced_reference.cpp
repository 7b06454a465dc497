#include "stages/simulate/balanced_reference.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "common/contact_forces.h"
#include "common/file_bytes.h"
#include "common/motion_integration.h"
#include "common/urdf.h"

#include <Eigen/SparseCholesky>
#include <Eigen/SparseCore>

namespace syn {
namespace {

// A sole point this close above the lowest of its support counts as touching (a heel lifting off
// leaves the toe edge).
constexpr double kTouchingBand = 0.01;
// An unplanted foot supports when its lowest sole point is this low and it moves slower than this
// (ContactForceOptions' defaults: a CMU walk's labels have no double support).
constexpr double kSupportHeight = 0.01;
constexpr double kSupportSpeed = 0.5;
// The vertical ground force the pendulum assumes is at least this share of the weight: a reference whose
// feet carry almost nothing (a jump's flight) would otherwise make it infinitely slow.
constexpr double kMinVerticalShare = 0.3;
// s: a foot's support or airborne stretch shorter than this is taken as its neighbours' (airborne_start).
constexpr double kShortestRun = 0.1;
// s: half the span over which the base's turn is measured (BalanceOptions::centre_line_turn).
constexpr double kTurnWindow = 0.5;
// The least-squares plan's weight on the shift itself (per m², against zmp errors per m²).
constexpr double kShiftWeight = 1e-6;

// Each sample replaced by its Gaussian-weighted mean over the samples within 3σ (σ in seconds).
void SmoothInTime(const std::vector<double>& time, double sigma, std::vector<Vector6d>& values) {
  if (!(sigma > 0)) return;
  const std::vector<Vector6d> raw = values;
  const size_t n = values.size();
  size_t first = 0;
  for (size_t i = 0; i < n; ++i) {
    while (time[i] - time[first] > 3 * sigma) ++first;
    Vector6d sum = Vector6d::Zero();
    double weights = 0;
    for (size_t j = first; j < n && time[j] - time[i] <= 3 * sigma; ++j) {
      const double w = std::exp(-0.5 * std::pow((time[j] - time[i]) / sigma, 2));
      sum += w * raw[j], weights += w;
    }
    values[i] = sum / weights;
  }
}

double Cross(const Eigen::Vector2d& a, const Eigen::Vector2d& b) { return a.x() * b.y() - a.y() * b.x(); }

}  // namespace

// Andrew's monotone chain.
void ConvexHull(std::vector<Eigen::Vector2d>& points, std::vector<Eigen::Vector2d>& hull) {
  std::sort(points.begin(), points.end(), [](const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
    return a.x() < b.x() || (a.x() == b.x() && a.y() < b.y());
  });
  hull.clear();
  if (points.size() < 3) {
    hull = points;
    return;
  }
  hull.resize(2 * points.size());
  size_t k = 0;
  for (size_t i = 0; i < points.size(); ++i) {
    while (k >= 2 && Cross(hull[k - 1] - hull[k - 2], points[i] - hull[k - 2]) <= 0) --k;
    hull[k++] = points[i];
  }
  for (size_t i = points.size() - 1, lower = k + 1; i-- > 0;) {
    while (k >= lower && Cross(hull[k - 1] - hull[k - 2], points[i] - hull[k - 2]) <= 0) --k;
    hull[k++] = points[i];
  }
  hull.resize(k - 1);
}

namespace {

Eigen::Vector2d ClosestOnSegment(const Eigen::Vector2d& p, const Eigen::Vector2d& a, const Eigen::Vector2d& b) {
  const Eigen::Vector2d ab = b - a;
  const double length_sq = ab.squaredNorm();
  const double s = length_sq > 0 ? std::clamp((p - a).dot(ab) / length_sq, 0.0, 1.0) : 0.0;
  return a + s * ab;
}

}  // namespace

Eigen::Vector2d ClosestInPolygon(const Eigen::Vector2d& p, const std::vector<Eigen::Vector2d>& hull) {
  if (hull.size() == 1) return hull[0];
  if (hull.size() == 2) return ClosestOnSegment(p, hull[0], hull[1]);
  bool inside = true;
  for (size_t i = 0; i < hull.size(); ++i) {
    if (Cross(hull[(i + 1) % hull.size()] - hull[i], p - hull[i]) < 0) inside = false;
  }
  if (inside) return p;
  Eigen::Vector2d best = hull[0];
  double best_sq = std::numeric_limits<double>::infinity();
  for (size_t i = 0; i < hull.size(); ++i) {
    const Eigen::Vector2d candidate = ClosestOnSegment(p, hull[i], hull[(i + 1) % hull.size()]);
    if ((candidate - p).squaredNorm() < best_sq) best_sq = (candidate - p).squaredNorm(), best = candidate;
  }
  return best;
}

std::vector<const ModelJoint*> FootChain(const Model& model, const std::string& foot_link) {
  std::vector<const ModelJoint*> chain;
  std::string link = foot_link;
  for (bool found = true; found;) {
    found = false;
    for (const ModelJoint& joint : model.joints()) {
      if (joint.child != link || joint.type == "free") continue;
      chain.push_back(&joint);
      link = joint.parent;
      found = true;
      break;
    }
  }
  return chain;
}

namespace {

// Per frame, how far (deg) the heading of `model`'s free base ranges within kTurnWindow either side:
// under 20° through the straight CMU walks' sway, 71° through CMU 09_12's turn on the spot. Zero for a
// model without a free base.
std::vector<double> BaseTurn(const MotionData& motion, const Model& model) {
  const size_t n = static_cast<size_t>(motion.frames());
  std::vector<double> heading(n, 0.0), turn(n, 0.0);
  if (!model.hasFreeBase()) return turn;
  for (size_t t = 0; t < n; ++t) {
    heading[t] = BaseYaw(&motion.q[t * static_cast<size_t>(model.nq())]);  // the free joint's quaternion leads q
    if (t > 0) heading[t] = heading[t - 1] + std::remainder(heading[t] - heading[t - 1], 2 * M_PI);  // unwrapped
  }
  for (size_t t = 0, first = 0, last = 0; t < n; ++t) {
    while (motion.time_s[t] - motion.time_s[first] > kTurnWindow) ++first;
    while (last + 1 < n && motion.time_s[last + 1] - motion.time_s[t] <= kTurnWindow) ++last;
    const auto [low, high] = std::minmax_element(heading.begin() + static_cast<std::ptrdiff_t>(first),
                                                 heading.begin() + static_cast<std::ptrdiff_t>(last) + 1);
    turn[t] = (*high - *low) * 180.0 / M_PI;
  }
  return turn;
}

// From each foot's per-frame support flags (the plan's supports), BalanceShift::airborne_start/_end. The flags
// flicker where a foot passes low and slow for a frame or two mid-swing (CMU 03_03's right foot 9 mm up for
// 67 ms before its touchdown): runs shorter than kShortestRun are merged into their neighbours, first the
// supporting ones, then the airborne ones.
void AirborneStretches(const std::vector<double>& time, std::vector<std::vector<char>>& supporting,
                       std::vector<std::vector<double>>& start, std::vector<std::vector<double>>& end) {
  const size_t n = time.size();
  for (std::vector<char>& flags : supporting) {
    for (const char value : {char{1}, char{0}}) {
      for (size_t t = 0; t < n;) {
        size_t after = t;
        while (after < n && flags[after] == flags[t]) ++after;
        const bool inside = t > 0 && after < n;
        if (flags[t] == value && inside && time[after] - time[t - 1] < kShortestRun) {
          std::fill(flags.begin() + static_cast<std::ptrdiff_t>(t), flags.begin() + static_cast<std::ptrdiff_t>(after),
                    static_cast<char>(1 - value));
        }
        t = after;
      }
    }
  }
  start.assign(supporting.size(), std::vector<double>(n, -1.0));
  end.assign(supporting.size(), std::vector<double>(n, -1.0));
  for (size_t f = 0; f < supporting.size(); ++f) {
    const std::vector<char>& flags = supporting[f];
    const auto airborne = [&](size_t t) { return !(flags[t] && flags[std::min(t + 1, n - 1)]); };
    for (size_t t = 0; t < n;) {
      if (!airborne(t)) {
        ++t;
        continue;
      }
      size_t last = t;
      while (last + 1 < n && airborne(last + 1)) ++last;
      std::fill(start[f].begin() + static_cast<std::ptrdiff_t>(t), start[f].begin() + static_cast<std::ptrdiff_t>(last) + 1, time[t]);
      std::fill(end[f].begin() + static_cast<std::ptrdiff_t>(t), end[f].begin() + static_cast<std::ptrdiff_t>(last) + 1,
                time[std::min(last + 1, n - 1)]);
      t = last + 1;
    }
  }
}

// Each vertex moved `margin` towards the centroid (at most to it): the polygon the planned ZMP keeps to.
void Shrink(std::vector<Eigen::Vector2d>& hull, double margin) {
  Eigen::Vector2d centroid = Eigen::Vector2d::Zero();
  for (const Eigen::Vector2d& v : hull) centroid += v;
  centroid /= static_cast<double>(hull.size());
  for (Eigen::Vector2d& v : hull) {
    const double distance = (v - centroid).norm();
    v = distance > margin ? Eigen::Vector2d(v + (centroid - v) * (margin / distance)) : centroid;
  }
}

// Links on each foot's chain up to the base (the free joint's child, excluded), and the fraction of a
// rigid shift of everything above the legs that reaches the centre of mass: the legs, fixed at the
// feet, follow half-way.
double LegLinks(const Model& model, const RobotMap& map, std::vector<bool>& leg_link) {
  leg_link.assign(model.linkNames().size(), false);
  std::vector<std::string> legs;
  for (const RobotFoot& foot : map.feet) {
    for (const ModelJoint* joint : FootChain(model, foot.link)) {
      const int index = model.findLinkIndex(joint->child);
      if (index < 0 || leg_link[static_cast<size_t>(index)]) break;
      leg_link[static_cast<size_t>(index)] = true;
      legs.push_back(joint->child);
    }
  }
  const RobotDescription urdf = ParseUrdf(ReadFileText(model.sourcePath()), model.sourcePath());
  double legs_mass = 0, total = 0;
  for (const UrdfLink& link : urdf.links) {
    total += link.inertial.mass;
    if (std::find(legs.begin(), legs.end(), link.name) != legs.end()) legs_mass += link.inertial.mass;
  }
  return total > 0 ? 1.0 - 0.5 * legs_mass / total : 1.0;
}

// D² x on the frame times (non-uniform second differences, zero slope beyond either end) as a sparse
// matrix of three diagonals.
Eigen::SparseMatrix<double> SecondDifference(const std::vector<double>& time) {
  const Eigen::Index n = static_cast<Eigen::Index>(time.size());
  std::vector<Eigen::Triplet<double>> entries;
  for (Eigen::Index i = 0; i < n && n > 1; ++i) {
    const size_t k = static_cast<size_t>(i);
    const double h_minus = i > 0 ? time[k] - time[k - 1] : time[1] - time[0];
    const double h_plus = i + 1 < n ? time[k + 1] - time[k] : time[k] - time[k - 1];
    const double a = 2 / ((h_minus + h_plus) * h_minus), c = 2 / ((h_minus + h_plus) * h_plus);
    entries.emplace_back(i, i > 0 ? i - 1 : i, a);
    entries.emplace_back(i, i, -a - c);
    entries.emplace_back(i, i + 1 < n ? i + 1 : i, c);
  }
  Eigen::SparseMatrix<double> d2(n, n);
  d2.setFromTriplets(entries.begin(), entries.end());
  return d2;
}

// The shift x whose pendulum zmp change x − η D² x is nearest to b in least squares, free at both ends.
// Held at rest for its first two frames (as it was), the plan could not be met: a take that begins
// mid-stride needs its centre of mass already moving towards the next stance foot (CMU 02_01: the plan's
// own zero-moment point 4-7 cm outside the left sole through the first left stance). Free, it is within
// 5 mm of the support in every frame, and the simulation starts on its first state (plan_start.h). A tiny
// weight on x keeps the system definite where η D² vanishes.
void SolvePendulum(const Eigen::SparseMatrix<double>& d2, const std::vector<double>& eta, const std::vector<double>& b,
                   std::vector<double>& x) {
  const Eigen::Index n = static_cast<Eigen::Index>(b.size());
  x.assign(b.size(), 0.0);
  if (n == 0) return;
  Eigen::SparseMatrix<double> identity(n, n);
  identity.setIdentity();
  Eigen::SparseMatrix<double> eta_diagonal(n, n);
  for (Eigen::Index i = 0; i < n; ++i) eta_diagonal.insert(i, i) = eta[static_cast<size_t>(i)];
  const Eigen::SparseMatrix<double> pendulum = identity - eta_diagonal * d2;
  Eigen::SparseMatrix<double> normal = pendulum.transpose() * pendulum;
  for (Eigen::Index i = 0; i < n; ++i) normal.coeffRef(i, i) += kShiftWeight;
  const Eigen::VectorXd rhs = pendulum.transpose() * Eigen::Map<const Eigen::VectorXd>(b.data(), n);
  Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> solver(normal);
  const Eigen::VectorXd solution = solver.solve(rhs);
  for (Eigen::Index i = 0; i < n; ++i) x[static_cast<size_t>(i)] = solution[i];
}

}  // namespace

BalanceShift PlanBalanceShift(const MotionData& motion, const Model& model, const RobotMap& map,
                              const BalanceOptions& options) {
  BalanceShift shift;
  const double alpha = LegLinks(model, map, shift.leg_link);
  const int64_t frames = motion.frames();
  const size_t n = static_cast<size_t>(frames);
  const int nq = model.nq(), nu = model.nu();
  const double mass = model.totalMass(), gravity = model.gravity();
  Workspace workspace(model);
  ContactForceOptions split_options;
  ContactForceSplit split(model, map.feet, split_options);
  ContactForceFrame wrench;
  Eigen::VectorXd q(nq), u(nu), udot(nu), tau(nu);
  std::vector<int> contact_column(map.feet.size(), -1);
  for (size_t f = 0; f < map.feet.size(); ++f) {
    for (size_t c = 0; c < motion.contact_feet.size(); ++c) {
      if (motion.contact_feet[c] == map.feet[f].side) contact_column[f] = static_cast<int>(c);
    }
  }
  shift.time = motion.time_s;
  shift.next_touchdown.assign(map.feet.size(), std::vector<int64_t>(static_cast<size_t>(frames), -1));
  for (size_t f = 0; f < map.feet.size(); ++f) {
    if (contact_column[f] < 0) continue;
    const auto planted_at = [&](int64_t t) {
      return motion.contact[static_cast<size_t>(t) * motion.contact_feet.size() + static_cast<size_t>(contact_column[f])] != 0;
    };
    int64_t next = -1;
    for (int64_t t = frames - 1; t >= 0; --t) {
      if (planted_at(t) && (t == 0 || !planted_at(t - 1))) next = t;
      shift.next_touchdown[f][static_cast<size_t>(t)] = next;
    }
  }
  std::vector<int> foot_links;
  for (const RobotFoot& foot : map.feet) foot_links.push_back(model.findLinkIndex(foot.link));
  std::vector<int64_t> planted(map.feet.size(), 0);
  std::vector<bool> supports(map.feet.size(), false);
  std::vector<Eigen::Vector3d> com(n), com_velocity(n);
  std::vector<Eigen::Vector3d>& angular_momentum = shift.angular_momentum;
  angular_momentum.resize(n);
  std::vector<Vector6d> residual(n);
  std::vector<std::vector<Eigen::Vector2d>>& hulls = shift.support;
  hulls.resize(n);
  std::vector<Eigen::Vector2d> support;
  std::vector<std::vector<char>> supporting(map.feet.size(), std::vector<char>(n, 0));
  std::vector<std::vector<Eigen::Vector3d>> sole(map.feet.size());
  // In a turn the plan's zero-moment point runs along the soles' centre lines. The margin leaves a 5-6 cm
  // G1 sole 0.8 cm off each side, so the plan may put its zero-moment point 1.8 cm off the centre line; a
  // turn's landing 3 cm off its aim (CMU 09_12's left foot at 4.05 s) then puts it past the sole's edge, the
  // capture error runs away through the single support, and 31 of 32 rounding-level runs fell there. On
  // the centre lines the ankles have the sole's half width either way. Session 50, 32 rounding-level runs of
  // the 21 CMU walks onto G1: in turns past 30 deg, 17.62 walks up as before (standard error 0.09), falls per
  // 100 steps 2.57 -> 2.41, and none of 09_12's falls begins at that landing (it goes 18-21 of its 29 steps
  // instead of 10-19); everywhere, 09_12 stayed up in one run but 03_01, 08_04, 08_07 and 12_02 fell more,
  // 17.34 (0.14). The centre-line points also decide whether a rolled foot counts as near the floor.
  const std::vector<double> turn = BaseTurn(motion, model);
  Eigen::Matrix<double, 6, Eigen::Dynamic> jacobian(6, nu);
  for (size_t t = 0; t < n; ++t) {
    q = Eigen::Map<const Eigen::VectorXd>(&motion.q[t * static_cast<size_t>(nq)], nq);
    u = Eigen::Map<const Eigen::VectorXd>(&motion.u[t * static_cast<size_t>(nu)], nu);
    udot = Eigen::Map<const Eigen::VectorXd>(&motion.udot[t * static_cast<size_t>(nu)], nu);
    workspace.setQ(q);
    workspace.setU(u);
    workspace.calcInverseDynamics(udot, tau);
    for (size_t f = 0; f < planted.size(); ++f) {
      planted[f] = contact_column[f] < 0 ? 0 : motion.contact[t * motion.contact_feet.size() + static_cast<size_t>(contact_column[f])];
    }
    split.split(workspace, u, tau, planted.data(), wrench);
    com[t] = workspace.findCenterOfMass();
    const Vector6d momentum = workspace.calcCentroidalMomentum();
    com_velocity[t] = momentum.tail<3>() / mass;
    angular_momentum[t] = momentum.head<3>();
    residual[t] = wrench.residual;
    // The support: planted feet, feet low and slow; else the lowest foot.
    double lowest_support = std::numeric_limits<double>::infinity();
    int lowest_foot = -1;
    double lowest_any = std::numeric_limits<double>::infinity();
    for (size_t f = 0; f < map.feet.size(); ++f) {
      const Eigen::Isometry3d pose = workspace.findLinkPose(foot_links[f]);
      workspace.calcFrameJacobian(foot_links[f], Eigen::Vector3d::Zero(), jacobian);
      const double speed = (jacobian.bottomRows<3>() * u).head<2>().norm();
      sole[f].clear();
      double lowest = std::numeric_limits<double>::infinity();
      const double width = turn[t] > options.centre_line_turn ? 0.0 : 1.0;
      for (const std::array<double, 3>& local : map.feet[f].sole_points) {
        sole[f].push_back(pose * Eigen::Vector3d(local[0], width * local[1], local[2]));
        lowest = std::min(lowest, sole[f].back().z());
      }
      if (lowest < lowest_any) lowest_any = lowest, lowest_foot = static_cast<int>(f);
      supports[f] = planted[f] != 0 || (lowest < kSupportHeight && speed < kSupportSpeed);
      if (supports[f]) lowest_support = std::min(lowest_support, lowest);
    }
    if (!std::isfinite(lowest_support) && lowest_foot >= 0) {
      supports[static_cast<size_t>(lowest_foot)] = true;
      lowest_support = lowest_any;
    }
    support.clear();
    for (size_t f = 0; f < map.feet.size(); ++f) {
      supporting[f][t] = supports[f] ? 1 : 0;
      if (!supports[f]) continue;
      for (const Eigen::Vector3d& point : sole[f]) {
        if (point.z() < lowest_support + kTouchingBand) support.emplace_back(point.x(), point.y());
      }
    }
    if (!support.empty()) {
      ConvexHull(support, hulls[t]);
      Shrink(hulls[t], options.margin);
    }
  }
  AirborneStretches(motion.time_s, supporting, shift.airborne_start, shift.airborne_end);
  // The retargeted accelerations are a spline's through per-frame solutions: the CMU walks' pelvis
  // reaches 123 m/s² in its first frames and the vertical force falls to zero for a frame here and
  // there, a zero-moment point metres away. What a robot must balance is the wrench's trend.
  SmoothInTime(motion.time_s, options.smoothing, residual);
  // The centre of mass the plan tracks, smoothed alike: its velocity from the per-frame solutions jitters
  // (CMU 02_01 onto G1: ±0.05 m/s at 12 Hz, the capture point ±1.2 cm that the feedback chased), and a plan
  // whose velocity is not the integral of its (smoothed) acceleration asks the feet for moments they
  // cannot give.
  std::vector<Vector6d> com_state(n);
  for (size_t t = 0; t < n; ++t) com_state[t] << com[t], com_velocity[t];
  SmoothInTime(motion.time_s, options.smoothing, com_state);
  for (size_t t = 0; t < n; ++t) com[t] = com_state[t].head<3>(), com_velocity[t] = com_state[t].tail<3>();
  std::vector<double>& eta = shift.eta;
  eta.resize(n);
  std::vector<double> correction_x(n), correction_y(n);
  shift.zmp.resize(n);
  for (size_t t = 0; t < n; ++t) {
    const Eigen::Vector3d moment = residual[t].head<3>(), force = residual[t].tail<3>();
    const double vertical = std::max(force.z(), kMinVerticalShare * mass * gravity);
    eta[t] = mass * com[t].z() / vertical;
    // Where the ground wrench (about the centre of mass) has no horizontal moment on the floor.
    const Eigen::Vector2d zmp(com[t].x() - (moment.y() + com[t].z() * force.x()) / vertical,
                              com[t].y() + (moment.x() - com[t].z() * force.y()) / vertical);
    const Eigen::Vector2d correction = hulls[t].empty() ? Eigen::Vector2d::Zero() : Eigen::Vector2d(ClosestInPolygon(zmp, hulls[t]) - zmp);
    if (correction.squaredNorm() > 0) ++shift.corrected_frames;
    shift.largest_zmp_correction = std::max(shift.largest_zmp_correction, correction.norm());
    shift.zmp[t] = zmp;  // the reference's; the plan's below
    correction_x[t] = correction.x();
    correction_y[t] = correction.y();
  }
  std::vector<double> x, y;
  const Eigen::SparseMatrix<double> d2 = SecondDifference(motion.time_s);
  SolvePendulum(d2, eta, correction_x, x);
  SolvePendulum(d2, eta, correction_y, y);
  const Eigen::Map<const Eigen::VectorXd> x_map(x.data(), static_cast<Eigen::Index>(n)), y_map(y.data(), static_cast<Eigen::Index>(n));
  const Eigen::VectorXd x_acceleration = d2 * x_map, y_acceleration = d2 * y_map;
  shift.position.resize(n), shift.velocity.resize(n), shift.acceleration.resize(n);
  for (size_t i = 0; i < n; ++i) {
    shift.position[i] = Eigen::Vector2d(x[i], y[i]) / alpha;
    shift.acceleration[i] = Eigen::Vector2d(x_acceleration[static_cast<Eigen::Index>(i)], y_acceleration[static_cast<Eigen::Index>(i)]) / alpha;
    shift.largest_shift = std::max(shift.largest_shift, shift.position[i].norm());
    // The zmp the plan realises: the reference's moved by x − η D² x (near the clamped one, not equal to it
    // where the start from rest or the least squares leave a difference).
    shift.zmp[i] += Eigen::Vector2d(x[i], y[i]) - eta[i] * alpha * shift.acceleration[i];
  }
  for (size_t i = 0; i < n; ++i) {
    const size_t before = i > 0 ? i - 1 : i, after = i + 1 < n ? i + 1 : i;
    const double span = motion.time_s[after] - motion.time_s[before];
    shift.velocity[i] = span > 0 ? Eigen::Vector2d((shift.position[after] - shift.position[before]) / span) : Eigen::Vector2d::Zero();
  }
  shift.com.resize(n), shift.com_velocity.resize(n), shift.com_acceleration.resize(n);
  for (size_t i = 0; i < n; ++i) {
    shift.com[i] = com[i].head<2>() + alpha * shift.position[i];
    shift.com_velocity[i] = com_velocity[i].head<2>() + alpha * shift.velocity[i];
    shift.com_acceleration[i] = residual[i].segment<2>(3) / mass + alpha * shift.acceleration[i];
  }
  shift.com_height.resize(n), shift.com_height_velocity.resize(n), shift.com_height_acceleration.resize(n);
  shift.angular_momentum_rate.resize(n);
  for (size_t i = 0; i < n; ++i) {
    shift.com_height[i] = com[i].z();
    shift.com_height_velocity[i] = com_velocity[i].z();
    shift.com_height_acceleration[i] = residual[i][5] / mass - gravity;
    shift.angular_momentum_rate[i] = residual[i].head<3>();
  }
  return shift;
}

}  // namespace syn
