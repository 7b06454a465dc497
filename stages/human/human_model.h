// syn-human: an anthropometric human model (URDF) and its robot map, for comparing a human's joint
// power with a robot's on the same retargeted motions.
//
// Segments follow the marker set's landmarks: pelvis (de Leva's lower trunk), torso (middle trunk)
// with the chest (upper trunk) fixed to it, head, thighs, shanks, feet, upper arms, forearms and hands.
// Masses, centres of mass and radii of gyration are de Leva (1996) Table 4 (de_leva.h), lengths de
// Leva's scaled by stature. The tree is the retargeter's: a free-floating pelvis; hips, lumbar, neck
// and shoulders 3 DoF, knees and elbows 1, ankles and wrists 2, forearm rotation 1 (32 joint DoF,
// plus the base's 6). Multi-DoF joints are chains of revolute joints through massless links. Zero pose: standing
// straight, arms hanging, palms facing the thighs; X forward, Y left, Z up; every link frame at its
// proximal joint centre with the pelvis's axes.
#pragma once

#include <limits>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "stages/human/de_leva.h"

namespace syn {

struct HumanModelOptions {
  // Stature (m) and body mass (kg). NaN = not given: de Leva's reference subject of that sex
  // (1.741 m and 73.0 kg male, 1.735 m and 61.9 kg female, de Leva 1996 Table 4), with a warning.
  double height = std::numeric_limits<double>::quiet_NaN();
  double mass = std::numeric_limits<double>::quiet_NaN();
  std::string sex = "m";  // f | m: which column of de Leva's table
  std::string name = "human_deleva";  // the URDF robot name (and the robot map's)

  bool IsValid(std::string* error) const;
  nlohmann::json ToJson() const;
};

struct HumanModelSummary {
  double height = 0, mass = 0;
  std::string sex;
  double standing_vertex_height = 0;  // of the zero pose, soles at z = 0 (m)
  int links = 0, joints = 0, degrees_of_freedom = 0;
  std::vector<std::string> warnings;

  std::string BriefReport() const;
};

struct HumanModelFiles {
  std::string urdf;       // URDF XML
  std::string robot_map;  // manifests/robots format (TOML)
};

// Throws UsageError for invalid options. Deterministic: the same options give the same bytes.
[[nodiscard]] HumanModelFiles BuildHumanModel(const HumanModelOptions& options, HumanModelSummary* summary);

}  // namespace syn
