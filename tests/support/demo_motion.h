// A real motion for tests: one bundled CMU BVH trial (datasets/demo/) through
// ingest and retarget onto G1, as the pipeline runs it. Computed once per
// test process and shared.
#pragma once

#include <string>

#include "common/motion_file.h"

namespace syn::testing {

// `trial`: a file stem in datasets/demo/, e.g. "05_02".
const MotionData& DemoMotionOnG1(const std::string& trial);

// Any CMU BVH (its T-pose first frame dropped) retargeted onto G1 with the stage's defaults; not cached.
MotionData CmuBvhOnG1(const std::string& bvh_path);

inline constexpr const char* kG1Urdf = "datasets/robots/unitree_g1/g1_29dof.urdf";
inline constexpr const char* kG1Map = "manifests/robots/g1.toml";

}  // namespace syn::testing
