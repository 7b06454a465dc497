// The shared CMU BVH trials by their class in ../shared/datasets/cmu_bvh/index.csv (walk, dance, ...): what
// the real-data sweeps iterate over, so they follow the index rather than a list of names.
#pragma once

#include <string>
#include <vector>

namespace syn::testing {

struct CmuTrial {
  std::string name;  // index.csv's trial column, e.g. "02_01"
  std::string file;  // its BVH under cmu_bvh/, e.g. "02/02_01.bvh"
  std::string motion_class;  // "walk", "dance", ...
};

// The trials whose motion_class is one of `classes`, in index order (empty when the index is absent).
[[nodiscard]] std::vector<CmuTrial> CmuTrials(const std::vector<std::string>& classes);

}  // namespace syn::testing
