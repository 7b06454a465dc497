// The Simbody side of common/model.h. Compiled as C++17 with -UNDEBUG (see
// CMakeLists.txt); nothing from here leaks into public headers.
#include "common/model.h"
#include "common/configuration_space.h"
#include "common/simbody/model_impl.h"

#include <Simbody.h>

#include <cmath>
#include <functional>
#include <limits>
#include <map>

#include "common/error.h"
#include "common/file_bytes.h"
#include "common/sha256.h"
#include "common/urdf.h"

namespace syn {
namespace {

// Rotation taking `from` (a unit axis of a mobilizer frame) onto the joint axis.
Eigen::Isometry3d AxisAlignment(const Eigen::Vector3d& from, const Eigen::Vector3d& axis) {
  Eigen::Isometry3d alignment = Eigen::Isometry3d::Identity();
  alignment.linear() = Eigen::Quaterniond::FromTwoVectors(from, axis).toRotationMatrix();
  return alignment;
}

}  // namespace

std::string_view FloatingBaseName(FloatingBase base) {
  switch (base) {
    case FloatingBase::kAuto: return "auto";
    case FloatingBase::kFree: return "free";
    case FloatingBase::kFixed: return "fixed";
  }
  return "?";
}

FloatingBase FloatingBaseFromName(std::string_view name) {
  if (name == "auto") return FloatingBase::kAuto;
  if (name == "free") return FloatingBase::kFree;
  if (name == "fixed") return FloatingBase::kFixed;
  throw UsageError("floating base must be auto, free or fixed, not '" + std::string(name) + "'");
}

namespace {

// A body being assembled: the URDF links merged into it by fixed joints.
struct BodyMassAccumulator {
  double mass = 0.0;
  Eigen::Vector3d first_moment = Eigen::Vector3d::Zero();   // Σ m c
  Eigen::Matrix3d inertia_about_origin = Eigen::Matrix3d::Zero();

  void add(const UrdfInertial& inertial, const Eigen::Isometry3d& link_in_body) {
    if (inertial.mass <= 0.0 && inertial.inertia.isZero()) return;
    const Eigen::Vector3d com = link_in_body * inertial.origin.translation();
    const Eigen::Matrix3d rotation = link_in_body.linear() * inertial.origin.linear();
    const Eigen::Matrix3d about_com = rotation * inertial.inertia * rotation.transpose();
    // Parallel-axis theorem: I_o = I_c + m (|c|² 1 − c cᵀ).
    inertia_about_origin += about_com + inertial.mass * (com.squaredNorm() * Eigen::Matrix3d::Identity() - com * com.transpose());
    mass += inertial.mass;
    first_moment += inertial.mass * com;
  }

  SimTK::MassProperties toSimbody() const {
    if (mass <= 0.0) return SimTK::MassProperties(0, SimTK::Vec3(0), SimTK::Inertia(0));
    const Eigen::Vector3d com = first_moment / mass;
    const Eigen::Matrix3d& I = inertia_about_origin;
    return SimTK::MassProperties(mass, SimTK::Vec3(com.x(), com.y(), com.z()),
                                 SimTK::Inertia(I(0, 0), I(1, 1), I(2, 2), I(0, 1), I(0, 2), I(1, 2)));
  }
};

}  // namespace

Model Model::Load(const std::string& urdf_path, const ModelOptions& options) {
  const std::string text = ReadFileText(urdf_path);
  RobotDescription urdf = ParseUrdf(text, urdf_path);
  auto impl = std::make_shared<Impl>(options.gravity);
  // A massless root with a floating joint (world -> base_link) is the free base written out.
  const std::string floating_root_note = options.floating_base == FloatingBase::kFixed
                                             ? WeldFloatingRootJoint(urdf)
                                             : TakeFloatingRootJointAsFreeBase(urdf);
  if (!floating_root_note.empty()) impl->notes.push_back(floating_root_note);
  impl->name = urdf.name;
  impl->path = urdf_path;
  impl->sha256 = Sha256Hex(text.data(), text.size());
  impl->warnings = urdf.warnings;

  // Children of each link, in file order.
  std::vector<std::vector<int>> child_joints(urdf.links.size());
  for (size_t j = 0; j < urdf.joints.size(); ++j) {
    const UrdfJoint& joint = urdf.joints[j];
    if (joint.type == UrdfJointType::kFloating) {
      throw DataError(Location::AtLine(urdf_path, joint.line),
                      "joint '" + joint.name + "': a floating joint is read only as the free base, from a massless "
                      "root link whose only joint it is (<link name=\"world\"/> -> base); inside the tree it is not "
                      "supported");
    }
    child_joints[static_cast<size_t>(urdf.findLink(joint.parent))].push_back(static_cast<int>(j));
  }
  const UrdfLink& root = urdf.links[static_cast<size_t>(urdf.root_link)];
  FloatingBase base = options.floating_base;
  if (base == FloatingBase::kAuto && !floating_root_note.empty()) base = FloatingBase::kFree;
  if (base == FloatingBase::kAuto) {
    bool virtual_chain = false;
    for (int j : child_joints[static_cast<size_t>(urdf.root_link)]) {
      virtual_chain = virtual_chain || urdf.joints[static_cast<size_t>(j)].type != UrdfJointType::kFixed;
    }
    // Virtual base links carry zero or token masses (HRP-4C: 1e-16 kg).
    base = (root.inertial.mass < 1e-6 && virtual_chain) ? FloatingBase::kFixed : FloatingBase::kFree;
  }
  impl->floating_base = base;

  // Assemble bodies depth-first from the root, so parents exist before children.
  impl->links.resize(urdf.links.size());
  std::vector<BodyMassAccumulator> masses;  // per our body number
  std::vector<int> body_of_link(urdf.links.size(), -1);
  std::vector<std::vector<int>> links_of_body;
  std::vector<int> body_parent_link;  // the link whose non-fixed joint created the body (-1 root)
  std::vector<int> body_joint;        // that joint (-1 root)

  // First pass: group links into bodies and accumulate mass properties.
  std::function<void(int, int, const Eigen::Isometry3d&)> group = [&](int link, int body, const Eigen::Isometry3d& in_body) {
    body_of_link[static_cast<size_t>(link)] = body;
    impl->links[static_cast<size_t>(link)].in_body = in_body;
    links_of_body[static_cast<size_t>(body)].push_back(link);
    masses[static_cast<size_t>(body)].add(urdf.links[static_cast<size_t>(link)].inertial, in_body);
    for (int j : child_joints[static_cast<size_t>(link)]) {
      const UrdfJoint& joint = urdf.joints[static_cast<size_t>(j)];
      const int child = urdf.findLink(joint.child);
      if (joint.type == UrdfJointType::kFixed) {
        group(child, body, in_body * joint.origin);
      } else {
        masses.emplace_back();
        links_of_body.emplace_back();
        body_parent_link.push_back(link);
        body_joint.push_back(j);
        group(child, static_cast<int>(masses.size()) - 1, Eigen::Isometry3d::Identity());
      }
    }
  };
  masses.emplace_back();
  links_of_body.emplace_back();
  body_parent_link.push_back(-1);
  body_joint.push_back(-1);
  group(urdf.root_link, 0, Eigen::Isometry3d::Identity());
  for (const UrdfLink& link : urdf.links) impl->total_mass += link.inertial.mass;

  // Second pass: mobilized bodies. Body 0 is the root: ground itself when
  // fixed, else a body on a Free mobilizer.
  std::vector<SimTK::MobilizedBodyIndex> mobilized(masses.size());
  if (base == FloatingBase::kFixed) {
    mobilized[0] = SimTK::GroundIndex;
  } else {
    SimTK::Body::Rigid body(masses[0].toSimbody());
    SimTK::MobilizedBody::Free free(impl->matter.Ground(), SimTK::Transform(), body, SimTK::Transform());
    mobilized[0] = free.getMobilizedBodyIndex();
    impl->joints.push_back({"floating_base", "free", "world", root.name, 0, 0});
  }
  for (size_t b = 1; b < masses.size(); ++b) {
    const UrdfJoint& joint = urdf.joints[static_cast<size_t>(body_joint[b])];
    const int parent_link = body_parent_link[b];
    SimTK::MobilizedBody& parent =
        impl->matter.updMobilizedBody(mobilized[static_cast<size_t>(body_of_link[static_cast<size_t>(parent_link)])]);
    const Eigen::Isometry3d joint_in_parent_body = impl->links[static_cast<size_t>(parent_link)].in_body * joint.origin;
    SimTK::Body::Rigid body(masses[b].toSimbody());
    const bool slides = joint.type == UrdfJointType::kPrismatic;
    // Pin turns about its mobilizer frame's Z, Slider moves along its X: align that axis with the URDF axis.
    const Eigen::Isometry3d alignment = AxisAlignment(slides ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitZ(), joint.axis);
    const SimTK::Transform inboard = ToSimbody(joint_in_parent_body * alignment);
    const SimTK::Transform outboard = ToSimbody(alignment);
    if (slides) {
      mobilized[b] = SimTK::MobilizedBody::Slider(parent, inboard, body, outboard)
                         .getMobilizedBodyIndex();
    } else {
      mobilized[b] = SimTK::MobilizedBody::Pin(parent, inboard, body, outboard)
                         .getMobilizedBodyIndex();
    }
  }
  for (size_t l = 0; l < urdf.links.size(); ++l) {
    impl->links[l].body = mobilized[static_cast<size_t>(body_of_link[l])];
    impl->link_names.push_back(urdf.links[l].name);
  }

  impl->system.realizeTopology();
  SimTK::State state = impl->system.getDefaultState();
  impl->system.realizeModel(state);
  impl->mobilities.resize(static_cast<size_t>(impl->matter.getNumBodies()));
  for (size_t b = 0; b < masses.size(); ++b) {
    if (mobilized[b] == SimTK::GroundIndex) continue;
    const SimTK::MobilizedBody& mobod = impl->matter.getMobilizedBody(mobilized[b]);
    Impl::Mobility& mobility = impl->mobilities[static_cast<size_t>(static_cast<int>(mobilized[b]))];
    mobility.u_index = mobod.getFirstUIndex(state);
    mobility.parent = static_cast<int>(mobod.getParentMobilizedBody().getMobilizedBodyIndex());
    if (b == 0) {
      mobility.kind = Impl::MobilityKind::kFree;
    } else {
      const UrdfJoint& joint = urdf.joints[static_cast<size_t>(body_joint[b])];
      mobility.kind = joint.type == UrdfJointType::kPrismatic ? Impl::MobilityKind::kSlider : Impl::MobilityKind::kPin;
      mobility.axis_in_body = joint.axis;
    }
  }
  impl->nq = state.getNQ();
  impl->nu = state.getNU();
  impl->coordinate_names.resize(static_cast<size_t>(impl->nq));
  impl->velocity_names.resize(static_cast<size_t>(impl->nu));
  impl->q_lower = Eigen::VectorXd::Constant(impl->nq, -std::numeric_limits<double>::infinity());
  impl->q_upper = Eigen::VectorXd::Constant(impl->nq, std::numeric_limits<double>::infinity());
  impl->u_limit = Eigen::VectorXd::Constant(impl->nu, std::numeric_limits<double>::infinity());
  impl->effort_limit = Eigen::VectorXd::Constant(impl->nu, std::numeric_limits<double>::infinity());
  if (base == FloatingBase::kFree) {
    const SimTK::MobilizedBody& free = impl->matter.getMobilizedBody(mobilized[0]);
    const int q0 = free.getFirstQIndex(state), u0 = free.getFirstUIndex(state);
    const char* q_names[] = {"base_qw", "base_qx", "base_qy", "base_qz", "base_x", "base_y", "base_z"};
    const char* u_names[] = {"base_wx", "base_wy", "base_wz", "base_vx", "base_vy", "base_vz"};
    for (int i = 0; i < 7; ++i) impl->coordinate_names[static_cast<size_t>(q0 + i)] = q_names[i];
    for (int i = 0; i < 6; ++i) impl->velocity_names[static_cast<size_t>(u0 + i)] = u_names[i];
  }
  // Joints in URDF file order, with their coordinates.
  std::map<int, size_t> body_of_joint;
  for (size_t b = 1; b < masses.size(); ++b) body_of_joint[body_joint[b]] = b;
  for (size_t j = 0; j < urdf.joints.size(); ++j) {
    const UrdfJoint& joint = urdf.joints[j];
    static const char* kTypeNames[] = {"revolute", "continuous", "prismatic", "fixed", "floating"};
    ModelJoint entry{joint.name, kTypeNames[static_cast<int>(joint.type)], joint.parent, joint.child, -1, -1, joint.origin, joint.axis};
    const auto found = body_of_joint.find(static_cast<int>(j));
    if (found != body_of_joint.end()) {
      const SimTK::MobilizedBody& mobod = impl->matter.getMobilizedBody(mobilized[found->second]);
      entry.q_index = mobod.getFirstQIndex(state);
      entry.u_index = mobod.getFirstUIndex(state);
      impl->coordinate_names[static_cast<size_t>(entry.q_index)] = joint.name;
      impl->velocity_names[static_cast<size_t>(entry.u_index)] = joint.name;
      if (joint.has_limits) {
        impl->q_lower[entry.q_index] = joint.lower;
        impl->q_upper[entry.q_index] = joint.upper;
      }
      const auto narrowed = options.joint_ranges.find(joint.name);
      if (narrowed != options.joint_ranges.end()) {
        double& lower = impl->q_lower[entry.q_index];
        double& upper = impl->q_upper[entry.q_index];
        lower = std::max(lower, narrowed->second[0]);
        upper = std::min(upper, narrowed->second[1]);
        if (!(lower < upper)) {
          throw UsageError("joint range [" + std::to_string(narrowed->second[0]) + ", " + std::to_string(narrowed->second[1]) +
                           "] for '" + joint.name + "' does not overlap the limits " + urdf_path + " gives it");
        }
      }
      if (joint.velocity > 0) impl->u_limit[entry.u_index] = joint.velocity;
      if (joint.effort > 0) impl->effort_limit[entry.u_index] = joint.effort;
    }
    impl->joints.push_back(entry);
  }
  // Unactuated velocities: a free base's six, or a virtual base chain's — walked from the massless root
  // through massless links (HRP-4C: p1..p3, r1..r3 end at the massive hip_base).
  impl->actuated.assign(static_cast<size_t>(impl->nu), true);
  if (base == FloatingBase::kFree) {
    const int u0 = impl->matter.getMobilizedBody(mobilized[0]).getFirstUIndex(state);
    for (int i = 0; i < 6; ++i) impl->actuated[static_cast<size_t>(u0 + i)] = false;
  } else {
    // A free base emulated by a chain of massless links: exactly three prismatic and three revolute joints.
    std::vector<int> chain;
    int prismatic = 0, link = urdf.root_link;
    while (urdf.links[static_cast<size_t>(link)].inertial.mass < 1e-6) {
      int moving_child = -1, moving_count = 0;
      for (int j : child_joints[static_cast<size_t>(link)]) {
        if (urdf.joints[static_cast<size_t>(j)].type != UrdfJointType::kFixed) {
          moving_child = j;
          ++moving_count;
        }
      }
      if (moving_count != 1) break;
      const UrdfJoint& joint = urdf.joints[static_cast<size_t>(moving_child)];
      prismatic += joint.type == UrdfJointType::kPrismatic;
      chain.push_back(impl->matter.getMobilizedBody(mobilized[body_of_joint[moving_child]]).getFirstUIndex(state));
      link = urdf.findLink(joint.child);
    }
    if (chain.size() == 6 && prismatic == 3) {
      for (int u : chain) impl->actuated[static_cast<size_t>(u)] = false;
    }
  }
  return Model(impl);
}

Model LoadModel(const std::string& urdf_path, std::string_view floating_base_name) {
  ModelOptions options;
  options.floating_base = FloatingBaseFromName(floating_base_name);
  return Model::Load(urdf_path, options);
}

const std::string& Model::name() const { return impl_->name; }
const std::string& Model::sourcePath() const { return impl_->path; }
const std::string& Model::sourceSha256() const { return impl_->sha256; }
FloatingBase Model::floatingBase() const { return impl_->floating_base; }
bool Model::hasFreeBase() const { return impl_->floating_base == FloatingBase::kFree; }
int Model::nq() const { return impl_->nq; }
int Model::nu() const { return impl_->nu; }
double Model::totalMass() const { return impl_->total_mass; }
const std::vector<bool>& Model::actuatedVelocities() const { return impl_->actuated; }
double Model::gravity() const { return impl_->gravity; }
const std::vector<std::string>& Model::coordinateNames() const { return impl_->coordinate_names; }
const std::vector<std::string>& Model::velocityNames() const { return impl_->velocity_names; }
const Eigen::VectorXd& Model::qLower() const { return impl_->q_lower; }
const Eigen::VectorXd& Model::qUpper() const { return impl_->q_upper; }
const Eigen::VectorXd& Model::uLimit() const { return impl_->u_limit; }
const Eigen::VectorXd& Model::effortLimit() const { return impl_->effort_limit; }
const std::vector<std::string>& Model::linkNames() const { return impl_->link_names; }
const std::vector<ModelJoint>& Model::joints() const { return impl_->joints; }
const std::vector<std::string>& Model::warnings() const { return impl_->warnings; }
const std::vector<std::string>& Model::notes() const { return impl_->notes; }

Eigen::VectorXd Model::defaultQ() const {
  Eigen::VectorXd q = Eigen::VectorXd::Zero(impl_->nq);
  if (hasFreeBase()) q[0] = 1.0;  // the Free mobilizer comes first: identity quaternion
  return q;
}

int Model::findLinkIndex(const std::string& link_name) const {
  for (size_t i = 0; i < impl_->link_names.size(); ++i) {
    if (impl_->link_names[i] == link_name) return static_cast<int>(i);
  }
  return -1;
}

int Model::freeBaseLink() const {
  for (const ModelJoint& joint : impl_->joints) {
    if (joint.type == "free") return findLinkIndex(joint.child);
  }
  return -1;
}

// ---- Workspace ------------------------------------------------------------------

// The state's q and u are views into one contiguous array; copy in bulk when
// they are, element by element (an out-of-line call each) when not.
void CopyInto(const Eigen::VectorXd& from, SimTK::Vector& to) {
  if (to.hasContiguousData()) {
    Eigen::Map<Eigen::VectorXd>(to.updContiguousScalarData(), to.size()) = from.head(to.size());
  } else {
    for (int i = 0; i < to.size(); ++i) to[i] = from[i];
  }
}

// A Free mobilizer's u: angular velocity (0..2), then the origin's linear velocity in ground (3..5).
constexpr int kFreeBaseVerticalVelocity = 5;

// The tree as plain numbers, for calcMassTimesAt. Each mobilized body (parents before children, as
// Simbody numbers them) is described in its mobilizer's outboard frame M rather than its body frame B:
// the children's inboard frames F and the body's mass properties are re-expressed in M once, here, so a
// pass needs one 3 × 3 product per body. A pin turns M about F's Z, a slider moves it along F's X, so a
// pin's axis passes through M's origin. Read from the realised system once per Workspace.
struct MassTimesTree {
  struct Body {
    Model::Impl::MobilityKind kind = Model::Impl::MobilityKind::kGround;
    int parent = 0;  // mobilized body index, 0 = ground
    int q_index = -1, u_index = -1;
    Eigen::Matrix3d R_PF = Eigen::Matrix3d::Identity();  // the inboard frame F in the parent's M frame
    Eigen::Vector3d p_PF = Eigen::Vector3d::Zero();
    double mass = 0;
    Eigen::Vector3d com = Eigen::Vector3d::Zero();                // in M
    Eigen::Matrix3d inertia_about_com = Eigen::Matrix3d::Zero();  // in M
  };
  // Per-call scratch, one entry per body (sized once: the pass never allocates).
  struct Pose {
    Eigen::Matrix3d R;                  // R_GM
    Eigen::Vector3d origin;             // M's origin in ground
    Eigen::Vector3d axis;               // pin or slider axis in ground
    Eigen::Matrix3d R_GF;               // the free base's inboard frame in ground
    Eigen::Vector3d angular, linear;    // angular velocity, velocity of M's origin
    Eigen::Vector3d momentum_angular, momentum_linear;  // of the subtree, about M's origin
    Eigen::Vector3d alpha, acceleration;  // angular acceleration, acceleration of M's origin (gravity: ground up)
    Eigen::Vector3d moment, force;        // inverse dynamics: of the subtree, about M's origin
  };
  std::vector<Body> bodies;  // index 0 = ground
  std::vector<Pose> poses;
  std::vector<int> link_body;                  // per URDF link: its mobilized body (0 = ground)
  std::vector<Eigen::Isometry3d> link_in_M;    // per URDF link: the link frame in that body's M frame
  Eigen::VectorXd q;         // the normalised configuration

  explicit MassTimesTree(const Model::Impl& model) {
    SimTK::State state = model.system.getDefaultState();
    model.system.realize(state, SimTK::Stage::Position);
    const int count = model.matter.getNumBodies();
    bodies.resize(static_cast<size_t>(count));
    poses.resize(static_cast<size_t>(count));
    q.resize(model.nq);
    // Each body frame B in its M frame (ground: identity); parents come first, so theirs is known.
    std::vector<Eigen::Isometry3d> B_in_M(static_cast<size_t>(count), Eigen::Isometry3d::Identity());
    for (int b = 1; b < count; ++b) {
      const SimTK::MobilizedBody& mobod = model.matter.getMobilizedBody(SimTK::MobilizedBodyIndex(b));
      Body& body = bodies[static_cast<size_t>(b)];
      body.kind = model.mobilities[static_cast<size_t>(b)].kind;
      body.parent = static_cast<int>(mobod.getParentMobilizedBody().getMobilizedBodyIndex());
      body.q_index = mobod.getFirstQIndex(state);
      body.u_index = mobod.getFirstUIndex(state);
      const Eigen::Isometry3d B_in_own_M = ToEigen(mobod.getOutboardFrame(state)).inverse();
      B_in_M[static_cast<size_t>(b)] = B_in_own_M;
      const Eigen::Isometry3d F_in_parent_M = B_in_M[static_cast<size_t>(body.parent)] * ToEigen(mobod.getInboardFrame(state));
      body.R_PF = F_in_parent_M.linear();
      body.p_PF = F_in_parent_M.translation();
      const SimTK::MassProperties& mass = mobod.getBodyMassProperties(state);
      const SimTK::Vec3 com = mass.getMassCenter();
      const SimTK::Mat33 inertia = mass.calcCentralInertia().toMat33();  // Simbody's is about B's origin
      Eigen::Matrix3d inertia_in_B;
      for (int i = 0; i < 3; ++i) {
        for (int j = 0; j < 3; ++j) inertia_in_B(i, j) = inertia(i, j);
      }
      body.mass = mass.getMass();
      body.com = B_in_own_M * Eigen::Vector3d(com[0], com[1], com[2]);
      body.inertia_about_com = B_in_own_M.linear() * inertia_in_B * B_in_own_M.linear().transpose();
    }
    for (const LinkPlacement& link : model.links) {
      link_body.push_back(static_cast<int>(link.body));
      link_in_M.push_back(B_in_M[static_cast<size_t>(static_cast<int>(link.body))] * link.in_body);
    }
  }

  // Both passes begin here: q (a free base's quaternion normalised, as Workspace::setQ does) and the
  // ground at rest at the origin.
  Pose& startAtGround(bool free_base, const Eigen::VectorXd& q_in) {
    q = q_in;
    if (free_base) {
      const double norm = q.head<4>().norm();
      if (norm > 0) q.head<4>() /= norm;
    }
    Pose& ground = poses[0];
    ground.R.setIdentity();
    ground.origin.setZero();
    ground.angular.setZero();
    ground.linear.setZero();
    return ground;
  }

  // p = A(q) u and tau = A(q) udot + b(q, u) + g(q) (Workspace::calcInverseDynamics) in one outward and one
  // inward pass; the poses stay for linkPose(). Gravity enters as the ground accelerating upward by g.
  void dynamics(bool free_base, double gravity, const Eigen::VectorXd& q_in, const Eigen::VectorXd& u,
                const Eigen::VectorXd& udot, Eigen::VectorXd& momentum, Eigen::VectorXd& tau) {
    using Kind = Model::Impl::MobilityKind;
    Pose& ground = startAtGround(free_base, q_in);
    ground.alpha.setZero();
    ground.acceleration = Eigen::Vector3d(0, 0, gravity);
    for (size_t b = 1; b < bodies.size(); ++b) {
      const Body& body = bodies[b];
      const Pose& parent = poses[static_cast<size_t>(body.parent)];
      Pose& pose = poses[b];
      const Eigen::Matrix3d R_GF = parent.R * body.R_PF;
      pose.origin = parent.origin + parent.R * body.p_PF;
      const Eigen::Vector3d arm = pose.origin - parent.origin;
      pose.angular = parent.angular;
      pose.linear = parent.linear + parent.angular.cross(arm);
      pose.alpha = parent.alpha;
      pose.acceleration = parent.acceleration + parent.alpha.cross(arm) + parent.angular.cross(parent.angular.cross(arm));
      // The mobility's own motion relative to the parent: an offset of M's origin, its velocity and
      // acceleration, and a relative angular velocity and acceleration, all in ground.
      Eigen::Vector3d offset = Eigen::Vector3d::Zero(), velocity = Eigen::Vector3d::Zero();
      Eigen::Vector3d acceleration = Eigen::Vector3d::Zero(), spin = Eigen::Vector3d::Zero();
      Eigen::Vector3d spin_rate = Eigen::Vector3d::Zero();
      switch (body.kind) {
        case Kind::kPin: {
          const double c = std::cos(q[body.q_index]), s = std::sin(q[body.q_index]);
          pose.R.col(0) = c * R_GF.col(0) + s * R_GF.col(1);
          pose.R.col(1) = c * R_GF.col(1) - s * R_GF.col(0);
          pose.R.col(2) = R_GF.col(2);
          pose.axis = R_GF.col(2);
          spin = pose.axis * u[body.u_index];
          spin_rate = pose.axis * udot[body.u_index];
          break;
        }
        case Kind::kSlider:
          pose.R = R_GF;
          pose.axis = R_GF.col(0);
          offset = pose.axis * q[body.q_index];
          velocity = pose.axis * u[body.u_index];
          acceleration = pose.axis * udot[body.u_index];
          break;
        case Kind::kFree: {
          const Eigen::Quaterniond rotation(q[body.q_index], q[body.q_index + 1], q[body.q_index + 2], q[body.q_index + 3]);
          pose.R = R_GF * rotation.toRotationMatrix();
          pose.R_GF = R_GF;
          offset = R_GF * q.segment<3>(body.q_index + 4);
          spin = R_GF * u.segment<3>(body.u_index);
          velocity = R_GF * u.segment<3>(body.u_index + 3);
          spin_rate = R_GF * udot.segment<3>(body.u_index);
          acceleration = R_GF * udot.segment<3>(body.u_index + 3);
          break;
        }
        case Kind::kGround:
          pose.R = R_GF;
          break;
      }
      // d/dt of a vector fixed in the parent: parent.angular × it.
      pose.origin += offset;
      pose.linear += parent.angular.cross(offset) + velocity;
      pose.acceleration += parent.alpha.cross(offset) + parent.angular.cross(parent.angular.cross(offset)) +
                           2.0 * parent.angular.cross(velocity) + acceleration;
      pose.angular += spin;
      pose.alpha += parent.angular.cross(spin) + spin_rate;

      const Eigen::Vector3d com = pose.R * body.com;
      const Eigen::Vector3d spin_in_M = pose.R.transpose() * pose.angular;
      const Eigen::Vector3d inertia_spin = pose.R * (body.inertia_about_com * spin_in_M);
      const Eigen::Vector3d inertia_alpha = pose.R * (body.inertia_about_com * (pose.R.transpose() * pose.alpha));
      pose.momentum_linear = body.mass * (pose.linear + pose.angular.cross(com));
      pose.momentum_angular = inertia_spin + com.cross(pose.momentum_linear);
      const Eigen::Vector3d com_acceleration =
          pose.acceleration + pose.alpha.cross(com) + pose.angular.cross(pose.angular.cross(com));
      pose.force = body.mass * com_acceleration;
      pose.moment = inertia_alpha + pose.angular.cross(inertia_spin) + com.cross(pose.force);
    }
    for (size_t b = bodies.size() - 1; b >= 1; --b) {
      const Body& body = bodies[b];
      const Pose& pose = poses[b];
      switch (body.kind) {
        case Kind::kPin:
          momentum[body.u_index] = pose.axis.dot(pose.momentum_angular);
          tau[body.u_index] = pose.axis.dot(pose.moment);
          break;
        case Kind::kSlider:
          momentum[body.u_index] = pose.axis.dot(pose.momentum_linear);
          tau[body.u_index] = pose.axis.dot(pose.force);
          break;
        case Kind::kFree:
          momentum.segment<3>(body.u_index) = pose.R_GF.transpose() * pose.momentum_angular;
          momentum.segment<3>(body.u_index + 3) = pose.R_GF.transpose() * pose.momentum_linear;
          tau.segment<3>(body.u_index) = pose.R_GF.transpose() * pose.moment;
          tau.segment<3>(body.u_index + 3) = pose.R_GF.transpose() * pose.force;
          break;
        case Kind::kGround:
          break;
      }
      if (body.parent > 0) {
        Pose& parent = poses[static_cast<size_t>(body.parent)];
        const Eigen::Vector3d arm = pose.origin - parent.origin;
        parent.momentum_linear += pose.momentum_linear;
        parent.momentum_angular += pose.momentum_angular + arm.cross(pose.momentum_linear);
        parent.force += pose.force;
        parent.moment += pose.moment + arm.cross(pose.force);
      }
    }
  }

  // A URDF link's world pose at the configuration of the last dynamics() call.
  Eigen::Isometry3d linkPose(int link) const {
    const Pose& pose = poses[static_cast<size_t>(link_body[static_cast<size_t>(link)])];
    Eigen::Isometry3d body = Eigen::Isometry3d::Identity();
    body.linear() = pose.R;
    body.translation() = pose.origin;
    return body * link_in_M[static_cast<size_t>(link)];
  }

  void massTimes(bool free_base, const Eigen::VectorXd& q_in, const Eigen::VectorXd& v, Eigen::VectorXd& out) {
    using Kind = Model::Impl::MobilityKind;
    startAtGround(free_base, q_in);
    // Outward: poses, velocities and each body's own momentum.
    for (size_t b = 1; b < bodies.size(); ++b) {
      const Body& body = bodies[b];
      const Pose& parent = poses[static_cast<size_t>(body.parent)];
      Pose& pose = poses[b];
      const Eigen::Matrix3d R_GF = parent.R * body.R_PF;
      pose.origin = parent.origin + parent.R * body.p_PF;
      pose.angular = parent.angular;
      pose.linear = parent.linear + parent.angular.cross(pose.origin - parent.origin);
      switch (body.kind) {
        case Kind::kPin: {
          const double c = std::cos(q[body.q_index]), s = std::sin(q[body.q_index]);
          pose.R.col(0) = c * R_GF.col(0) + s * R_GF.col(1);
          pose.R.col(1) = c * R_GF.col(1) - s * R_GF.col(0);
          pose.R.col(2) = R_GF.col(2);
          pose.axis = R_GF.col(2);
          pose.angular += pose.axis * v[body.u_index];  // about an axis through M's origin
          break;
        }
        case Kind::kSlider:
          pose.R = R_GF;
          pose.axis = R_GF.col(0);
          pose.origin += pose.axis * q[body.q_index];
          pose.linear += pose.axis * v[body.u_index];  // the parent's rotation carried the extra offset too
          pose.linear += parent.angular.cross(pose.axis * q[body.q_index]);
          break;
        case Kind::kFree: {
          // q: M's orientation and origin in F; u: its angular velocity and origin velocity, both in F.
          const Eigen::Quaterniond rotation(q[body.q_index], q[body.q_index + 1], q[body.q_index + 2], q[body.q_index + 3]);
          const Eigen::Vector3d offset = R_GF * q.segment<3>(body.q_index + 4);
          pose.R = R_GF * rotation.toRotationMatrix();
          pose.R_GF = R_GF;
          pose.linear += parent.angular.cross(offset) + R_GF * v.segment<3>(body.u_index + 3);
          pose.origin += offset;
          pose.angular += R_GF * v.segment<3>(body.u_index);
          break;
        }
        case Kind::kGround:
          pose.R = R_GF;
          break;
      }
      const Eigen::Vector3d com = pose.R * body.com;
      pose.momentum_linear = body.mass * (pose.linear + pose.angular.cross(com));
      pose.momentum_angular = pose.R * (body.inertia_about_com * (pose.R.transpose() * pose.angular)) +
                              com.cross(pose.momentum_linear);
    }
    // Inward: subtree momenta, and each mobility's share of them.
    for (size_t b = bodies.size() - 1; b >= 1; --b) {
      const Body& body = bodies[b];
      const Pose& pose = poses[b];
      switch (body.kind) {
        case Kind::kPin:  // the subtree's angular momentum about the joint axis
          out[body.u_index] = pose.axis.dot(pose.momentum_angular);
          break;
        case Kind::kSlider:
          out[body.u_index] = pose.axis.dot(pose.momentum_linear);
          break;
        case Kind::kFree:
          out.segment<3>(body.u_index) = pose.R_GF.transpose() * pose.momentum_angular;
          out.segment<3>(body.u_index + 3) = pose.R_GF.transpose() * pose.momentum_linear;
          break;
        case Kind::kGround:
          break;
      }
      if (body.parent > 0) {
        Pose& parent = poses[static_cast<size_t>(body.parent)];
        parent.momentum_linear += pose.momentum_linear;
        parent.momentum_angular += pose.momentum_angular + (pose.origin - parent.origin).cross(pose.momentum_linear);
      }
    }
  }
};

// A(q) by the composite-rigid-body algorithm, everything in ground about the ground origin: each
// body's subtree inertia I_c (6 × 6, (angular, linear) rows) from the leaves in, then A(i, j) =
// s_jᵀ I_c(body of i) s_i for i's own velocities and its ancestors' j, with s the velocity's motion
// axis (angular velocity, velocity of the point at the ground origin). O(n · depth); the poses come
// from a massTimes pass with zero velocities.
namespace {

using Matrix6d = Eigen::Matrix<double, 6, 6>;
using Vector6d = Eigen::Matrix<double, 6, 1>;

void MassMatrixFromTree(MassTimesTree& tree, bool free_base, const Eigen::VectorXd& q, std::vector<Matrix6d>& composite,
                        std::vector<Vector6d>& axes, std::vector<int>& body_of_velocity, Eigen::VectorXd& zero,
                        Eigen::VectorXd& momenta, Eigen::MatrixXd& mass) {
  using Kind = Model::Impl::MobilityKind;
  const int nu = static_cast<int>(mass.rows());
  zero.setZero(nu);
  momenta.resize(nu);
  tree.massTimes(free_base, q, zero, momenta);
  const size_t count = tree.bodies.size();
  composite.resize(count);
  axes.resize(static_cast<size_t>(nu));
  body_of_velocity.resize(static_cast<size_t>(nu));
  for (size_t b = 1; b < count; ++b) {
    const MassTimesTree::Body& body = tree.bodies[b];
    const MassTimesTree::Pose& pose = tree.poses[b];
    const Eigen::Vector3d com = pose.origin + pose.R * body.com;
    const Eigen::Matrix3d c = CrossMatrix(com);
    Matrix6d& inertia = composite[b];
    inertia.topLeftCorner<3, 3>() = pose.R * body.inertia_about_com * pose.R.transpose() - body.mass * c * c;
    inertia.topRightCorner<3, 3>() = body.mass * c;
    inertia.bottomLeftCorner<3, 3>() = -body.mass * c;
    inertia.bottomRightCorner<3, 3>() = body.mass * Eigen::Matrix3d::Identity();
    const auto set_axis = [&](int u, const Eigen::Vector3d& angular, const Eigen::Vector3d& linear) {
      axes[static_cast<size_t>(u)] << angular, linear;
      body_of_velocity[static_cast<size_t>(u)] = static_cast<int>(b);
    };
    switch (body.kind) {
      case Kind::kPin:
        set_axis(body.u_index, pose.axis, pose.origin.cross(pose.axis));
        break;
      case Kind::kSlider:
        set_axis(body.u_index, Eigen::Vector3d::Zero(), pose.axis);
        break;
      case Kind::kFree:
        for (int k = 0; k < 3; ++k) {
          set_axis(body.u_index + k, pose.R_GF.col(k), pose.origin.cross(pose.R_GF.col(k)));
          set_axis(body.u_index + 3 + k, Eigen::Vector3d::Zero(), pose.R_GF.col(k));
        }
        break;
      case Kind::kGround:
        break;
    }
  }
  for (size_t b = count - 1; b >= 1; --b) {
    const int parent = tree.bodies[b].parent;
    if (parent > 0) composite[static_cast<size_t>(parent)] += composite[b];
  }
  // Velocities are numbered from the root out, so a body's ancestors' velocities all come before its
  // own; within a free joint, every one of its six sees the same composite inertia.
  for (int i = 0; i < nu; ++i) {
    const int b = body_of_velocity[static_cast<size_t>(i)];
    const Vector6d force = composite[static_cast<size_t>(b)] * axes[static_cast<size_t>(i)];
    for (int j = 0; j <= i; ++j) {
      // j's body is an ancestor of i's (or the same): walk up from i's body.
      int a = b;
      const int target = body_of_velocity[static_cast<size_t>(j)];
      while (a > 0 && a != target) a = tree.bodies[static_cast<size_t>(a)].parent;
      mass(i, j) = mass(j, i) = a == target ? axes[static_cast<size_t>(j)].dot(force) : 0.0;
    }
  }
}

}  // namespace

struct Workspace::Impl {
  const Model::Impl& model;
  MassTimesTree tree;
  SimTK::State state;
  Eigen::VectorXd q, u;
  SimTK::Vector scratch_in, scratch_out, zero_mobility_forces;
  SimTK::Matrix jacobian, mass_matrix;
  std::vector<Matrix6d> composite_inertia;  // calcMassMatrix's scratch
  std::vector<Vector6d> velocity_axes;
  std::vector<int> body_of_velocity;
  Eigen::VectorXd zero_velocity, zero_momenta;
  // Gravity as body forces (moment about and force at each body origin, in
  // ground), for the inverse/forward dynamics operators, which take applied
  // forces explicitly. Computed here from each body's mass and COM because
  // Force::Gravity's cache needs Stage::Dynamics, which would also evaluate
  // everything else.
  SimTK::Vector_<SimTK::SpatialVec> gravity_forces, zero_body_forces;
  bool gravity_current = false;

  const SimTK::Vector_<SimTK::SpatialVec>& gravityForces() {
    if (gravity_current) return gravity_forces;
    const int bodies = model.matter.getNumBodies();
    for (SimTK::MobilizedBodyIndex b(1); b < bodies; ++b) {
      const SimTK::MobilizedBody& body = model.matter.getMobilizedBody(b);
      const SimTK::MassProperties& mass = body.getBodyMassProperties(state);
      const SimTK::Vec3 com_in_ground = body.getBodyRotation(state) * mass.getMassCenter();
      const SimTK::Vec3 force(0, 0, -mass.getMass() * model.gravity);
      gravity_forces[b] = SimTK::SpatialVec(com_in_ground % force, force);
    }
    gravity_current = true;
    return gravity_forces;
  }

  explicit Impl(const Model::Impl& model_in)
      : model(model_in),
        tree(model_in),
        state(model_in.system.getDefaultState()),
        q(Eigen::VectorXd::Zero(model_in.nq)),
        u(Eigen::VectorXd::Zero(model_in.nu)),
        scratch_in(model_in.nu, 0.0),
        scratch_out(model_in.nu, 0.0),
        zero_mobility_forces(model_in.nu, 0.0),
        jacobian(6, model_in.nu),
        gravity_forces(model_in.matter.getNumBodies(), SimTK::SpatialVec(SimTK::Vec3(0), SimTK::Vec3(0))),
        zero_body_forces(model_in.matter.getNumBodies(), SimTK::SpatialVec(SimTK::Vec3(0), SimTK::Vec3(0))) {
    if (model.floating_base == FloatingBase::kFree) q[0] = 1.0;
    model.system.realizeModel(state);
    for (int i = 0; i < model.nq; ++i) state.updQ()[i] = q[i];
    model.system.realize(state, SimTK::Stage::Velocity);
  }

  // SimTK::Vector's element access goes through an out-of-line helper per
  // element; the scratch vectors own contiguous storage, so copy through it.
  void toScratch(const Eigen::VectorXd& v) {
    Eigen::Map<Eigen::VectorXd>(scratch_in.updContiguousScalarData(), model.nu) = v.head(model.nu);
  }
  void fromScratch(Eigen::VectorXd& out) const {
    out = Eigen::Map<const Eigen::VectorXd>(scratch_out.getContiguousScalarData(), model.nu);
  }
};

Workspace::Workspace(const Model& model) : model_(model), impl_(std::make_unique<Impl>(model.impl())) {}
Workspace::~Workspace() = default;
Workspace::Workspace(Workspace&&) noexcept = default;
Workspace& Workspace::operator=(Workspace&&) noexcept = default;

void Workspace::setQ(const Eigen::VectorXd& q) {
  Impl& impl = *impl_;
  CheckSize("Workspace::setQ: q", model_.nq(), q.size());
  impl.q = q;
  if (model_.hasFreeBase()) {
    const double norm = impl.q.head<4>().norm();
    if (norm > 0) impl.q.head<4>() /= norm;
  }
  CopyInto(impl.q, impl.state.updQ());
  impl.model.system.realize(impl.state, SimTK::Stage::Position);
  impl.gravity_current = false;
}

void Workspace::setU(const Eigen::VectorXd& u) {
  CheckSize("Workspace::setU: u", model_.nu(), u.size());
  Impl& impl = *impl_;
  impl.u = u;
  CopyInto(u, impl.state.updU());
  impl.model.system.realize(impl.state, SimTK::Stage::Velocity);
}

const Eigen::VectorXd& Workspace::getQ() const { return impl_->q; }
const Eigen::VectorXd& Workspace::getU() const { return impl_->u; }

Eigen::Isometry3d Workspace::findLinkPose(int link) const {
  const LinkPlacement& placement = impl_->model.links[static_cast<size_t>(link)];
  const SimTK::Transform& body = impl_->model.matter.getMobilizedBody(placement.body).getBodyTransform(impl_->state);
  return ToEigen(body) * placement.in_body;
}

void Workspace::calcFrameJacobian(int link, const Eigen::Vector3d& point_in_link,
                                  Eigen::Matrix<double, 6, Eigen::Dynamic>& jacobian) {
  // Analytic, walking from the link's body to the root: each revolute joint
  // contributes (a, a × (p − o)), each prismatic (0, a), the free base
  // (e_i, e_i × (p − o_base)) for its angular and (0, e_i) for its linear
  // velocities — all in ground. About 1 µs against 8 µs for Simbody's
  // general calcFrameJacobian, which the model tests check it against.
  Impl& impl = *impl_;
  const Model::Impl& model = impl.model;
  const LinkPlacement& placement = model.links[static_cast<size_t>(link)];
  jacobian.resize(6, model.nu);
  jacobian.setZero();
  const SimTK::Transform& link_body = model.matter.getMobilizedBody(placement.body).getBodyTransform(impl.state);
  const Eigen::Vector3d point = ToEigen(link_body) * (placement.in_body * point_in_link);
  for (int body = static_cast<int>(placement.body); body > 0;) {
    const Model::Impl::Mobility& mobility = model.mobilities[static_cast<size_t>(body)];
    const SimTK::Transform& pose = model.matter.getMobilizedBody(SimTK::MobilizedBodyIndex(body)).getBodyTransform(impl.state);
    const Eigen::Vector3d origin(pose.p()[0], pose.p()[1], pose.p()[2]);
    switch (mobility.kind) {
      case Model::Impl::MobilityKind::kPin: {
        const SimTK::Vec3 axis = pose.R() * SimTK::Vec3(mobility.axis_in_body.x(), mobility.axis_in_body.y(), mobility.axis_in_body.z());
        const Eigen::Vector3d a(axis[0], axis[1], axis[2]);
        jacobian.col(mobility.u_index).head<3>() = a;
        jacobian.col(mobility.u_index).tail<3>() = a.cross(point - origin);
        break;
      }
      case Model::Impl::MobilityKind::kSlider: {
        const SimTK::Vec3 axis = pose.R() * SimTK::Vec3(mobility.axis_in_body.x(), mobility.axis_in_body.y(), mobility.axis_in_body.z());
        jacobian.col(mobility.u_index).tail<3>() = Eigen::Vector3d(axis[0], axis[1], axis[2]);
        break;
      }
      case Model::Impl::MobilityKind::kFree:
        for (int i = 0; i < 3; ++i) {
          const Eigen::Vector3d e = Eigen::Vector3d::Unit(i);
          jacobian.col(mobility.u_index + i).head<3>() = e;
          jacobian.col(mobility.u_index + i).tail<3>() = e.cross(point - origin);
          jacobian.col(mobility.u_index + 3 + i).tail<3>() = e;
        }
        break;
      case Model::Impl::MobilityKind::kGround:
        break;
    }
    body = mobility.parent;
  }
}

void Workspace::calcFrameJacobianWithSimbody(int link, const Eigen::Vector3d& point_in_link,
                                             Eigen::Matrix<double, 6, Eigen::Dynamic>& jacobian) {
  Impl& impl = *impl_;
  const LinkPlacement& placement = impl.model.links[static_cast<size_t>(link)];
  jacobian.resize(6, impl.model.nu);
  if (placement.body == SimTK::GroundIndex) {
    jacobian.setZero();
    return;
  }
  const Eigen::Vector3d station = placement.in_body * point_in_link;
  impl.model.matter.calcFrameJacobian(impl.state, placement.body, SimTK::Vec3(station.x(), station.y(), station.z()),
                                      impl.jacobian);
  for (int r = 0; r < 6; ++r) {
    for (int c = 0; c < impl.model.nu; ++c) jacobian(r, c) = impl.jacobian(r, c);
  }
}

void Workspace::calcMassTimes(const Eigen::VectorXd& v, Eigen::VectorXd& out) {
  impl_->toScratch(v);
  impl_->model.matter.multiplyByM(impl_->state, impl_->scratch_in, impl_->scratch_out);
  impl_->fromScratch(out);
}

void Workspace::calcMassTimesAt(const Eigen::VectorXd& q, const Eigen::VectorXd& v, Eigen::VectorXd& out) {
  out.resize(impl_->model.nu);
  impl_->tree.massTimes(model_.hasFreeBase(), q, v, out);
}

void Workspace::calcDynamicsAt(const Eigen::VectorXd& q, const Eigen::VectorXd& u, const Eigen::VectorXd& udot,
                               Eigen::VectorXd& momentum, Eigen::VectorXd& tau) {
  momentum.resize(impl_->model.nu);
  tau.resize(impl_->model.nu);
  impl_->tree.dynamics(model_.hasFreeBase(), impl_->model.gravity, q, u, udot, momentum, tau);
}

Eigen::Isometry3d Workspace::findLinkPoseAtLastDynamics(int link) const { return impl_->tree.linkPose(link); }

void Workspace::calcMassMatrix(Eigen::MatrixXd& mass) {
  Impl& impl = *impl_;
  mass.resize(impl.model.nu, impl.model.nu);
  MassMatrixFromTree(impl.tree, model_.hasFreeBase(), impl.q, impl.composite_inertia, impl.velocity_axes,
                     impl.body_of_velocity, impl.zero_velocity, impl.zero_momenta, mass);
}

void Workspace::calcMassMatrixWithSimbody(Eigen::MatrixXd& mass) {
  impl_->model.matter.calcM(impl_->state, impl_->mass_matrix);
  const int n = impl_->model.nu;
  mass.resize(n, n);
  for (int c = 0; c < n; ++c) {
    for (int r = 0; r < n; ++r) mass(r, c) = impl_->mass_matrix(r, c);
  }
}

void Workspace::calcMassInverseTimes(const Eigen::VectorXd& v, Eigen::VectorXd& out) {
  impl_->toScratch(v);
  impl_->model.matter.multiplyByMInv(impl_->state, impl_->scratch_in, impl_->scratch_out);
  impl_->fromScratch(out);
}

void Workspace::calcMomentum(Eigen::VectorXd& p) { calcMassTimes(impl_->u, p); }

Eigen::Matrix<double, 6, 1> Workspace::calcCentroidalMomentum() {
  const SimTK::SpatialVec momentum = impl_->model.matter.calcSystemCentralMomentum(impl_->state);
  Eigen::Matrix<double, 6, 1> result;
  for (int i = 0; i < 3; ++i) result[i] = momentum[0][i], result[3 + i] = momentum[1][i];
  return result;
}

double Workspace::calcKineticEnergy() { return impl_->model.matter.calcKineticEnergy(impl_->state); }

void Workspace::calcInverseDynamics(const Eigen::VectorXd& udot, Eigen::VectorXd& tau) {
  Impl& impl = *impl_;
  impl.toScratch(udot);
  if (impl.model.floating_base == FloatingBase::kFree) {
    // Gravity on every body is the same as the ground accelerating upward by
    // g. A Free mobilizer's linear velocities are in ground (its inboard
    // frame is the ground frame), so adding g to the base's vertical
    // acceleration moves every body by exactly that uniform acceleration, and
    // saves building per-body gravity forces (a cache lookup per body).
    // calcForwardDynamics keeps the explicit forces: the tests check one
    // against the other.
    impl.scratch_in[kFreeBaseVerticalVelocity] += impl.model.gravity;
    impl.model.matter.calcResidualForceIgnoringConstraints(impl.state, impl.zero_mobility_forces, impl.zero_body_forces,
                                                           impl.scratch_in, impl.scratch_out);
  } else {
    impl.model.matter.calcResidualForceIgnoringConstraints(impl.state, impl.zero_mobility_forces, impl.gravityForces(),
                                                           impl.scratch_in, impl.scratch_out);
  }
  impl.fromScratch(tau);
}

void Workspace::calcForwardDynamics(const Eigen::VectorXd& tau, Eigen::VectorXd& udot) {
  // udot = A⁻¹ (tau − (b + g)), with b + g the inverse dynamics of zero
  // acceleration: two O(n) operators, and no need to realise Stage::Dynamics.
  Impl& impl = *impl_;
  impl.scratch_in = 0.0;
  impl.model.matter.calcResidualForceIgnoringConstraints(impl.state, impl.zero_mobility_forces, impl.gravityForces(),
                                                         impl.scratch_in, impl.scratch_out);
  for (int i = 0; i < impl.model.nu; ++i) impl.scratch_in[i] = tau[i] - impl.scratch_out[i];
  impl.model.matter.multiplyByMInv(impl.state, impl.scratch_in, impl.scratch_out);
  impl.fromScratch(udot);
}

Eigen::Matrix<double, 6, 1> Workspace::calcFrameBiasAcceleration(int link, const Eigen::Vector3d& point_in_link) {
  Impl& impl = *impl_;
  const LinkPlacement& placement = impl.model.links[static_cast<size_t>(link)];
  Eigen::Matrix<double, 6, 1> bias = Eigen::Matrix<double, 6, 1>::Zero();
  if (placement.body == SimTK::GroundIndex) return bias;
  const Eigen::Vector3d station = placement.in_body * point_in_link;
  const SimTK::SpatialVec simbody_bias = impl.model.matter.calcBiasForFrameJacobian(
      impl.state, placement.body, SimTK::Vec3(station.x(), station.y(), station.z()));
  for (int i = 0; i < 3; ++i) bias[i] = simbody_bias[0][i], bias[3 + i] = simbody_bias[1][i];
  return bias;
}

Eigen::Vector3d Workspace::findCenterOfMass() {
  const SimTK::Vec3 com = impl_->model.matter.calcSystemMassCenterLocationInGround(impl_->state);
  return {com[0], com[1], com[2]};
}

}  // namespace syn
