#include "stages/human/human_model.h"

#include <array>
#include <cmath>
#include <cstdio>
#include <iterator>
#include <sstream>

#include "common/error.h"

namespace syn {
namespace {

constexpr double kPi = 3.14159265358979323846;

// ---- Geometry de Leva's table does not give (fractions of stature unless noted) -------------------
// Ankle joint centre above the sole, and foot width: Winter D.A. (2009) Biomechanics and Motor Control of
// Human Movement, 4th ed., Fig. 4.1 (after Drillis & Contini 1966): 0.039 H and 0.055 H.
constexpr double kAnkleHeight = 0.039;
constexpr double kFootWidth = 0.055;
// Estimates (not from a table): hip joint centres 0.10 H apart (0.174 m at 1.741 m), shoulder joint
// centres 0.20 H apart (0.348 m; Winter's biacromial breadth is 0.259 H, the joint centres lie inside the
// acromions) and 0.06 H below C7; the heel 20 % of the foot length behind the ankle; de Leva's heel and
// toe-tip line at half the ankle height. They place joints, not masses: the de Leva parameters of
// every segment are used as tabulated.
constexpr double kHipJointSpacing = 0.10;
constexpr double kShoulderJointSpacing = 0.20;
constexpr double kShoulderDropBelowC7 = 0.06;
constexpr double kHeelBehindAnkle = 0.20;  // of the foot length

// The retargeter bounds each frame's joint step by the URDF velocity limit; 20 rad/s lies above
// human joint angular velocities in the archive's motions (walks, dances, jumps), so it only stops
// the IK from jumping between solution branches, as the robots' limits do.
constexpr double kJointVelocityLimit = 20.0;  // rad/s

// ---- Joints --------------------------------------------------------------------------------------
// Axes for the left side (or the midline) in the parent's frame at the zero pose, signed so that a
// positive angle is the OpenSim coordinate's positive direction (flexion, adduction, internal rotation,
// dorsiflexion, inversion, extension of the lumbar spine, pronation, ulnar deviation). The right side
// mirrors them through the sagittal plane: (x, y, z) -> (-x, y, -z).
// Ranges (degrees): OpenSim's full-body model of Hamner, Seth & Delp (2010) J. Biomech. 43:2709 (gait2392
// legs and trunk, arms after Holzbaur et al. 2005), as in ../shared/datasets/trc/opensim_hamner_running/
// subject02_registered.osim: hip_flexion/adduction/rotation ±120, knee_angle -120..10 (our sign: flexion
// positive), ankle_angle ±60 (the file's left side; its right reads ±90), subtalar_angle ±90,
// lumbar_extension/bending/rotation ±90, arm_flex ±90, arm_add -120..90, arm_rot ±90, elbow_flex 0..150,
// wrist_flex ±70, wrist_dev -25..35. That model has no neck: cervical flexion and extension 45, lateral
// bending 45, rotation 60 are the AAOS averages (American Academy of Orthopaedic Surgeons 1965, Joint
// Motion: Method of Measuring and Recording). Forearm rotation: the file's pro_sup is 0..90 from full
// supination; our zero is the neutral forearm of hanging arms, so ±90 about it.
struct JointSpec {
  const char* name;
  double axis[3];
  double lower_deg, upper_deg;
};

constexpr JointSpec kHip[] = {{"hip_flexion", {0, -1, 0}, -120, 120},
                              {"hip_adduction", {-1, 0, 0}, -120, 120},
                              {"hip_rotation", {0, 0, -1}, -120, 120}};
constexpr JointSpec kKnee[] = {{"knee", {0, 1, 0}, -10, 120}};
constexpr JointSpec kAnkle[] = {{"ankle_flexion", {0, -1, 0}, -60, 60}, {"subtalar", {-1, 0, 0}, -90, 90}};
constexpr JointSpec kLumbar[] = {{"lumbar_extension", {0, -1, 0}, -90, 90},
                                 {"lumbar_bending", {1, 0, 0}, -90, 90},
                                 {"lumbar_rotation", {0, 0, 1}, -90, 90}};
constexpr JointSpec kNeck[] = {
    {"neck_flexion", {0, 1, 0}, -45, 45}, {"neck_bending", {1, 0, 0}, -45, 45}, {"neck_rotation", {0, 0, 1}, -60, 60}};
constexpr JointSpec kShoulder[] = {{"shoulder_flexion", {0, -1, 0}, -90, 90},
                                   {"shoulder_adduction", {-1, 0, 0}, -120, 90},
                                   {"shoulder_rotation", {0, 0, -1}, -90, 90}};
constexpr JointSpec kElbow[] = {{"elbow", {0, -1, 0}, 0, 150}, {"forearm_rotation", {0, 0, -1}, -90, 90}};
constexpr JointSpec kWrist[] = {{"wrist_flexion", {-1, 0, 0}, -70, 70}, {"wrist_deviation", {0, 1, 0}, -25, 35}};

std::string Number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.12g", value);
  return text;
}

std::string Triple(double x, double y, double z) {
  std::string triple = Number(x);
  triple.append(" ").append(Number(y)).append(" ").append(Number(z));
  return triple;
}
// (Appended piecewise: GCC 12 warns falsely on chains of std::string operator+.)
std::string TomlPoint(double x, double y, double z) {
  std::string point = "[";
  point.append(Number(x)).append(", ").append(Number(y)).append(", ").append(Number(z)).append("]");
  return point;
}

class UrdfWriter {
 public:
  explicit UrdfWriter(const std::string& name) { xml_ << "<?xml version=\"1.0\"?>\n<robot name=\"" << name << "\">\n"; }

  // A segment: mass at `com` (link frame), principal moments along the link axes.
  void segmentLink(const std::string& name, double mass, const double com[3], const double moments[3]) {
    xml_ << "  <link name=\"" << name << "\">\n    <inertial>\n      <origin xyz=\"" << Triple(com[0], com[1], com[2])
         << "\" rpy=\"0 0 0\"/>\n      <mass value=\"" << Number(mass) << "\"/>\n      <inertia ixx=\""
         << Number(moments[0]) << "\" ixy=\"0\" ixz=\"0\" iyy=\"" << Number(moments[1]) << "\" iyz=\"0\" izz=\""
         << Number(moments[2]) << "\"/>\n    </inertial>\n  </link>\n";
    ++links_;
  }
  void masslessLink(const std::string& name) {
    xml_ << "  <link name=\"" << name << "\"/>\n";
    ++links_;
  }
  void revolute(const std::string& name, const std::string& parent, const std::string& child, const double origin[3],
                const double axis[3], double lower_deg, double upper_deg) {
    xml_ << "  <joint name=\"" << name << "\" type=\"revolute\">\n    <parent link=\"" << parent
         << "\"/>\n    <child link=\"" << child << "\"/>\n    <origin xyz=\"" << Triple(origin[0], origin[1], origin[2])
         << "\" rpy=\"0 0 0\"/>\n    <axis xyz=\"" << Triple(axis[0], axis[1], axis[2]) << "\"/>\n    <limit lower=\""
         << Number(lower_deg * kPi / 180) << "\" upper=\"" << Number(upper_deg * kPi / 180)
         << "\" effort=\"0\" velocity=\"" << Number(kJointVelocityLimit) << "\"/>\n  </joint>\n";
    ++joints_, ++dofs_;
  }
  void fixed(const std::string& name, const std::string& parent, const std::string& child, const double origin[3]) {
    xml_ << "  <joint name=\"" << name << "\" type=\"fixed\">\n    <parent link=\"" << parent
         << "\"/>\n    <child link=\"" << child << "\"/>\n    <origin xyz=\"" << Triple(origin[0], origin[1], origin[2])
         << "\" rpy=\"0 0 0\"/>\n  </joint>\n";
    ++joints_;
  }
  // A chain of revolute joints from `parent` (at `origin`) to `child`: massless links between them.
  void jointChain(const std::string& side, const JointSpec* specs, size_t count, const std::string& parent,
                  const std::string& child, const double origin[3]) {
    std::string from = parent;
    for (size_t j = 0; j < count; ++j) {
      const std::string name = side + specs[j].name;
      double axis[3] = {specs[j].axis[0], specs[j].axis[1], specs[j].axis[2]};
      if (side == "right_") axis[0] = -axis[0], axis[2] = -axis[2];
      const std::string to = j + 1 == count ? child : name + "_link";
      if (j + 1 < count) masslessLink(to);
      static constexpr double kZero[3] = {0, 0, 0};
      revolute(name, from, to, j == 0 ? origin : kZero, axis, specs[j].lower_deg, specs[j].upper_deg);
      from = to;
    }
  }
  std::string finish() {
    xml_ << "</robot>\n";
    return xml_.str();
  }
  int links() const { return links_; }
  int joints() const { return joints_; }
  int dofs() const { return dofs_; }

 private:
  std::ostringstream xml_;
  int links_ = 0, joints_ = 0, dofs_ = 0;
};

// A segment's mass, CoM and principal moments from the table. The CoM lies on the segment's line from
// `origin_point` towards `other_point` (link frame); `long_axis` is the index of the link axis along the
// segment (2 = z; the foot's is x), the transverse radius goes with y, the sagittal with the remaining one.
struct SegmentInertia {
  double mass = 0, com[3] = {0, 0, 0}, moments[3] = {0, 0, 0};
};

SegmentInertia Inertia(const SegmentParameters& segment, double mass_scale, double length, const double origin_point[3],
                       const double other_point[3], int long_axis) {
  SegmentInertia inertia;
  inertia.mass = segment.mass_percent * mass_scale;
  const double c = segment.com_percent / 100;
  for (int i = 0; i < 3; ++i) inertia.com[i] = origin_point[i] + c * (other_point[i] - origin_point[i]);
  auto moment = [&](double radius_percent) {
    const double radius = radius_percent / 100 * length;
    return inertia.mass * radius * radius;
  };
  const int sagittal_axis = long_axis == 2 ? 0 : 2;
  inertia.moments[long_axis] = moment(segment.radius_longitudinal_percent);
  inertia.moments[1] = moment(segment.radius_transverse_percent);
  inertia.moments[sagittal_axis] = moment(segment.radius_sagittal_percent);
  return inertia;
}

}  // namespace

bool HumanModelOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& message) {
    if (error) *error = message;
    return false;
  };
  if (sex != "f" && sex != "m" && sex != "female" && sex != "male") return fail("--sex must be f or m");
  if (!std::isnan(height) && !(height >= 1.0 && height <= 2.5)) return fail("--height must be in [1, 2.5] m");
  if (!std::isnan(mass) && !(mass >= 20 && mass <= 300)) return fail("--mass must be in [20, 300] kg");
  if (name.empty() || name.find_first_of("\"<>&'") != std::string::npos) return fail("--name must be a plain name");
  return true;
}

nlohmann::json HumanModelOptions::ToJson() const {
  return {{"height", std::isnan(height) ? nlohmann::json() : nlohmann::json(height)},
          {"mass", std::isnan(mass) ? nlohmann::json() : nlohmann::json(mass)},
          {"sex", sex},
          {"name", name}};
}

std::string HumanModelSummary::BriefReport() const {
  std::ostringstream out;
  out << "de Leva " << (sex == "f" ? "female" : "male") << ", " << Number(height) << " m, " << Number(mass) << " kg: "
      << links << " links, " << joints << " joints, " << degrees_of_freedom
      << " joint DoF + free base; standing vertex height " << Number(standing_vertex_height) << " m";
  return out.str();
}

HumanModelFiles BuildHumanModel(const HumanModelOptions& options, HumanModelSummary* summary) {
  std::string error;
  if (!options.IsValid(&error)) throw UsageError(error);
  const Sex sex = SexFromName(options.sex);
  const AnthropometricTable& table = DeLevaTable4(sex);
  HumanModelSummary report;
  report.sex = std::string(SexName(sex));
  report.height = options.height, report.mass = options.mass;
  if (std::isnan(report.height)) {
    report.height = table.stature_mm / 1000;
    report.warnings.push_back("no height given: de Leva's reference " + std::string(sex == Sex::kFemale ? "female" : "male") +
                              " stature " + Number(report.height) + " m");
  }
  if (std::isnan(report.mass)) {
    report.mass = table.body_mass_kg;
    report.warnings.push_back("no mass given: de Leva's reference " + std::string(sex == Sex::kFemale ? "female" : "male") +
                              " body mass " + Number(report.mass) + " kg");
  }
  const double H = report.height;
  // Masses: the table's percentages of the body mass, normalised by their sum (99.99 % for females) so
  // the segments add up to exactly the subject's mass.
  const double mass_scale = report.mass / table.wholeBodyMassPercent();
  auto length = [&](Segment segment) { return table[segment].length_mm / table.stature_mm * H; };
  const double head = length(Segment::kHead), upper_trunk = length(Segment::kUpperTrunk);
  const double middle_trunk = length(Segment::kMiddleTrunk), lower_trunk = length(Segment::kLowerTrunk);
  const double upper_arm = length(Segment::kUpperArm), forearm = length(Segment::kForearm), hand = length(Segment::kHand);
  const double thigh = length(Segment::kThigh), shank = length(Segment::kShank), foot = length(Segment::kFoot);
  const double ankle_height = kAnkleHeight * H, heel_x = -kHeelBehindAnkle * foot, heel_toe_z = -ankle_height / 2;

  UrdfWriter urdf(options.name);
  auto segment = [&](const std::string& link, Segment which, const double origin_point[3], const double other_point[3],
                     int long_axis = 2) {
    const SegmentInertia inertia = Inertia(table[which], mass_scale, length(which), origin_point, other_point, long_axis);
    urdf.segmentLink(link, inertia.mass, inertia.com, inertia.moments);
  };
  // Vertical segments, link frame at the lower (or upper) joint: the segment's endpoints in that frame.
  auto up = [](double z) { return std::array<double, 3>{0, 0, z}; };

  // Pelvis = lower trunk, frame at the mid-hip point (MIDH); its origin endpoint OMPH is above.
  segment("pelvis", Segment::kLowerTrunk, up(lower_trunk).data(), up(0).data());
  // Trunk: lumbar joint at the omphalion; torso = middle trunk (XYPH above, OMPH at the frame);
  // chest = upper trunk (CERV above, XYPH at the frame), fixed to the torso.
  urdf.jointChain("", kLumbar, std::size(kLumbar), "pelvis", "torso", up(lower_trunk).data());
  segment("torso", Segment::kMiddleTrunk, up(middle_trunk).data(), up(0).data());
  urdf.fixed("sternum", "torso", "chest", up(middle_trunk).data());
  segment("chest", Segment::kUpperTrunk, up(upper_trunk).data(), up(0).data());
  urdf.jointChain("", kNeck, std::size(kNeck), "chest", "head", up(upper_trunk).data());
  segment("head", Segment::kHead, up(head).data(), up(0).data());  // origin VERT above, C7 at the frame

  for (const std::string side : {"left_", "right_"}) {
    const double y_sign = side == "left_" ? 1.0 : -1.0;
    const double hip[3] = {0, y_sign * kHipJointSpacing * H / 2, 0};
    urdf.jointChain(side, kHip, std::size(kHip), "pelvis", side + "thigh", hip);
    segment(side + "thigh", Segment::kThigh, up(0).data(), up(-thigh).data());
    urdf.jointChain(side, kKnee, std::size(kKnee), side + "thigh", side + "shank", up(-thigh).data());
    segment(side + "shank", Segment::kShank, up(0).data(), up(-shank).data());
    urdf.jointChain(side, kAnkle, std::size(kAnkle), side + "shank", side + "foot", up(-shank).data());
    const double heel[3] = {heel_x, 0, heel_toe_z}, toe[3] = {heel_x + foot, 0, heel_toe_z};
    segment(side + "foot", Segment::kFoot, heel, toe, /*long_axis=*/0);

    const double shoulder[3] = {0, y_sign * kShoulderJointSpacing * H / 2, upper_trunk - kShoulderDropBelowC7 * H};
    urdf.jointChain(side, kShoulder, std::size(kShoulder), "chest", side + "upper_arm", shoulder);
    segment(side + "upper_arm", Segment::kUpperArm, up(0).data(), up(-upper_arm).data());
    urdf.jointChain(side, kElbow, std::size(kElbow), side + "upper_arm", side + "forearm", up(-upper_arm).data());
    segment(side + "forearm", Segment::kForearm, up(0).data(), up(-forearm).data());
    urdf.jointChain(side, kWrist, std::size(kWrist), side + "forearm", side + "hand", up(-forearm).data());
    segment(side + "hand", Segment::kHand, up(0).data(), up(-hand).data());
  }
  HumanModelFiles files;
  files.urdf = urdf.finish();
  report.links = urdf.links(), report.joints = urdf.joints(), report.degrees_of_freedom = urdf.dofs();
  report.standing_vertex_height = ankle_height + shank + thigh + lower_trunk + middle_trunk + upper_trunk + head;

  // The robot map: the paper's Table I tasks on the matching segments; soles from the foot geometry.
  std::ostringstream map;
  map << "# Generated by syn-human (" << options.ToJson().dump() << "): de Leva (1996) segments, see README.\n"
      << "robot = \"" << options.name << "\"\nfloating_base = \"free\"\npriority_weights = [1.0, 0.1, 0.001]\n"
      << "# A person's planted foot rolls down from its heel after heel strike and onto its toes before push-off;\n"
      << "# when a detected contact ends (the ankle 5-7.5 cm up, contact_detection.h) it is pitched about 20°.\n"
      << "# Held flat (max_roll 0, the default), CMU 02_01's first frame, the right heel just down, bent the knee\n"
      << "# 41° and the next frame 32° (800 rad/s²), and the walk cost 5.0 W/kg instead of 3.3.\n"
      << "max_roll = 0.4\n";
  struct Task {
    const char *landmark, *link, *type;
    int priority;
  };
  for (const Task& task : {Task{"pelvis", "pelvis", "pose", 1}, Task{"left_foot", "left_foot", "pose", 1},
                           Task{"right_foot", "right_foot", "pose", 1}, Task{"left_hand", "left_hand", "pose", 1},
                           Task{"right_hand", "right_hand", "pose", 1}, Task{"head", "head", "orientation", 1},
                           Task{"upper_torso", "torso", "orientation", 2},
                           Task{"left_elbow", "left_forearm", "orientation", 2},
                           Task{"right_elbow", "right_forearm", "orientation", 2}}) {
    map << "\n[[task]]\nlandmark = \"" << task.landmark << "\"\nlink = \"" << task.link << "\"\ntype = \"" << task.type
        << "\"\npriority = " << task.priority << "\n";
  }
  map << "\n[posture]\npriority = 3\nweight = 1.0\n\n# q_ref: the zero pose (standing straight, arms hanging).\n"
      << "[reference_stance]\n"
      << "\n# The calibration frame BVH converters put before the take (CMU: a T-pose; syn-ingest --drop-first-frame\n"
      << "# keeps it aside): arms out sideways, palms down. Captures that carry it are retargeted relative to it,\n"
      << "# so the first frame of the take (mid-stride in a walk) is not taken for the straight-legged zero pose.\n"
      << "[calibration_stance]\nleft_shoulder_adduction = " << Number(-M_PI / 2) << "\nright_shoulder_adduction = "
      << Number(-M_PI / 2) << "\n";
  const double toe_x = heel_x + foot, half_width = kFootWidth * H / 2;
  for (const char* side : {"left", "right"}) {
    map << "\n# Sole: heel to toe tip, foot width " << Number(kFootWidth) << " H, " << Number(ankle_height)
        << " m below the ankle joint centre.\n[feet." << side << "]\nlink = \"" << side << "_foot\"\nsole_points = ["
        << TomlPoint(heel_x, half_width, -ankle_height) << ", " << TomlPoint(heel_x, -half_width, -ankle_height) << ", "
        << TomlPoint(toe_x, half_width, -ankle_height) << ", " << TomlPoint(toe_x, -half_width, -ankle_height) << "]\n";
  }
  files.robot_map = map.str();
  if (summary) *summary = std::move(report);
  return files;
}

}  // namespace syn
