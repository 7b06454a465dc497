// CMU BVH joints as the 22 SMPL joint names of HumanML3D (the names the
// humanml3d22 marker set reads), for each cgspeed naming convention
// (../shared/datasets/cmu_bvh/SOURCES.md). The Daz-friendly conversion has
// no toe joints: its foot's End Site (the toe tip, `lFoot_end` after ingest)
// stands for SMPL's foot joint.
//
// CMU skeletons put several joints at one place (LowerBack at Hips, Neck and
// the collars at Spine1): a marker there would make the landmark axes
// degenerate, so SMPL's spine1 / neck / collars take the next distinct joint
// (Spine, Neck1, the shoulder joints), as close as CMU's skeleton allows. The
// Daz figure has distinct abdomen, chest, neck and collar joints and uses them.
#pragma once

#include <array>
#include <string>
#include <vector>

namespace syn {

enum class BvhConvention { kMotionBuilder, kMax, kDaz, kNone };

// From the capture's body (joint) names.
[[nodiscard]] BvhConvention DetectBvhConvention(const std::vector<std::string>& bodies);

struct JointMarker {
  const char* smpl;       // HumanML3D / SMPL joint name
  const char* mirror;     // its left/right counterpart (itself on the midline)
  const char* bvh[3];     // the BVH joint, indexed by BvhConvention: MotionBuilder-, 3dsMax-, Daz-friendly
};

// The 22 SMPL joints in HumanML3D order.
[[nodiscard]] const std::array<JointMarker, 22>& SmplJointMarkers();

}  // namespace syn
