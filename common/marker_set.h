// Marker sets: how the landmarks the retargeter tracks are built from a
// capture's markers, bones or joints (DESIGN.md, Method: Landmarks).
//
// A marker-set file (manifests/markersets/NAME.toml) defines each landmark
// either from a body of the capture (BVH bone, Motive rigid body: its pose is
// used as is) or from named points (markers, or body positions such as
// HumanML3D joints): origin = mean of the points; two axes, each the
// difference of two point means, made orthonormal by Gram–Schmidt in the
// order given; the third axis completes a right-handed frame.
//
// Point names may list alternates, "LASI|LFWT": the first the capture has is
// used. Subject prefixes ("Male:") are ignored and case does not matter.
#pragma once

#include <array>
#include <string>
#include <vector>

namespace syn {

// The landmarks of the paper (Table I), in this order everywhere, then the shoulders (glenohumeral joint
// centres), hips and knees (joint centres), position only: no robot task tracks them, they measure the
// subject's arm and leg lengths for the retargeter's proportions (stages/retarget/stance_alignment.h). A
// marker set may leave any landmark out.
inline constexpr std::array<const char*, 15> kLandmarkNames = {
    "pelvis",     "upper_torso", "head",      "left_hand",     "right_hand",     "left_elbow",
    "right_elbow", "left_foot",  "right_foot", "left_shoulder", "right_shoulder", "left_hip",
    "right_hip",  "left_knee",   "right_knee"};

// One name with its alternates: {"LASI", "LFWT"}.
using PointChoice = std::vector<std::string>;

struct AxisDefinition {
  char axis = 'x';                 // which axis of the landmark frame this is
  std::vector<PointChoice> from;   // the axis points from mean(from) ...
  std::vector<PointChoice> to;     // ... to mean(to)
};

struct LandmarkDefinition {
  std::string name;                     // one of kLandmarkNames
  int line = 0;                         // where it is defined, for messages
  PointChoice body;                     // non-empty: take this capture body's pose
  std::vector<PointChoice> origin;      // else: origin = mean of these points
  std::vector<AxisDefinition> axes;     // 0 (position only) or 2 axes, primary first
};

struct MarkerSet {
  std::string name;
  std::string description;
  std::string file;  // where it was read from
  std::vector<LandmarkDefinition> landmarks;
};

// Reads and validates a marker-set TOML file; errors are DataError at
// file:line (unknown landmark name, an axis missing, a body and points both given ...).
[[nodiscard]] MarkerSet LoadMarkerSet(const std::string& path);
[[nodiscard]] MarkerSet ParseMarkerSet(const std::string& toml_text, const std::string& file_name);

}  // namespace syn
