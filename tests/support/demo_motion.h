// A real motion for tests: one bundled CMU BVH trial (datasets/demo/) through
// ingest and retarget onto G1, as the pipeline runs it. Computed once per
// test executable (CmuBvhOnG1's cache) and shared within a process.
#pragma once

#include <string>
#include <vector>

#include "common/motion_file.h"

namespace syn::testing {

// `trial`: a file stem in datasets/demo/, e.g. "05_02".
const MotionData& DemoMotionOnG1(const std::string& trial);

// Any CMU BVH (its T-pose first frame dropped) retargeted onto G1 with the stage's defaults. Kept in the
// build's test cache (SYN_TEST_CACHE_DIR) for the other tests of the same executable: each test runs in
// a process of its own, and under the sanitizers a retarget takes 10-20 s. The cache is keyed by its
// inputs' contents and the executable's size and time, and a motion is cached only if its file reads
// back exactly as computed.
MotionData CmuBvhOnG1(const std::string& bvh_path);

// Whether `a` and `b` hold the same doubles bit for bit (NaN included, which == never matches: a landmark
// the retargeter could not measure has a NaN error).
bool SameBits(const std::vector<double>& a, const std::vector<double>& b);

inline constexpr const char* kG1Urdf = "datasets/robots/unitree_g1/g1_29dof.urdf";
inline constexpr const char* kG1Map = "manifests/robots/g1.toml";
inline constexpr const char* kCmuMarkerset = "manifests/markersets/cmu-bvh.toml";

}  // namespace syn::testing
