// Where tests find the shared real datasets (../shared/datasets beside the
// repository). Tests that need them call SYN_REQUIRE_SHARED(path), which skips
// the test with a visible reason when the file is absent.
#pragma once

#include <filesystem>
#include <string>

#include <gtest/gtest.h>

namespace syn::testing {

inline std::string SharedPath(const std::string& relative) {
  return std::string(SYN_SHARED_DATASETS) + "/" + relative;
}
inline std::string SourcePath(const std::string& relative) {
  return std::string(SYN_SOURCE_DIR) + "/" + relative;
}
inline std::string BinPath(const std::string& tool) { return std::string(SYN_BIN_DIR) + "/" + tool; }

}  // namespace syn::testing

#define SYN_REQUIRE_SHARED(relative)                                                          \
  do {                                                                                        \
    if (!std::filesystem::exists(::syn::testing::SharedPath(relative))) {                     \
      GTEST_SKIP() << "shared dataset absent: " << ::syn::testing::SharedPath(relative);      \
    }                                                                                         \
  } while (0)
