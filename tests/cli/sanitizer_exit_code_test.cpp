// In the sanitizer build (make sanitize-test), a leak or undefined behaviour must end a tool with its own exit
// code (the Makefile's SANITIZER_EXIT_CODE, 86), never 1: the tools exit 1 for bad data, and the CLI tests that
// expect 1 from a refusal would pass on a leak report. The Makefile sets ASAN_OPTIONS / LSAN_OPTIONS /
// UBSAN_OPTIONS for the whole ctest run; this test fails when they are missing or wrong. It runs this very test
// binary as the probe: with SYN_SANITIZER_PROBE set, a static initialiser leaks or overflows and exits 0.
#include <gtest/gtest.h>
#include <unistd.h>

#include <climits>
#include <cstdlib>
#include <cstring>
#include <string>

#include "tests/support/run_command.h"

namespace syn::testing {
namespace {

void* volatile leak_sink = nullptr;

[[gnu::noinline]] void LeakSomeMemory() {
  for (int i = 0; i < 64; ++i) {
    leak_sink = std::malloc(256);
    std::memset(leak_sink, i, 256);
  }
  leak_sink = nullptr;
}

[[gnu::noinline]] int OverflowASignedInt() {
  volatile int largest = INT_MAX;
  return largest + 1;  // undefined: the UB probe
}

[[maybe_unused]] const bool probe_ran = [] {
  const char* probe = std::getenv("SYN_SANITIZER_PROBE");
  if (probe == nullptr) return false;
  if (std::strcmp(probe, "leak") == 0) LeakSomeMemory();
  if (std::strcmp(probe, "ub") == 0) std::exit(OverflowASignedInt() == 0 ? 0 : 0);
  std::exit(0);  // a leak is reported at exit
}();

TEST(SanitizerExitCode, LeakAndUndefinedBehaviourDoNotLookLikeBadData) {
#ifndef SYN_SANITIZED_BUILD
  GTEST_SKIP() << "needs the sanitizer build (make sanitize-test); this build has no sanitizers";
#else
  (void)probe_ran;
  char self[4096] = {};
  ASSERT_GT(::readlink("/proc/self/exe", self, sizeof(self) - 1), 0);
  for (const char* probe : {"leak", "ub"}) {
    SCOPED_TRACE(probe);
    const CommandResult result = RunCommand(std::string("SYN_SANITIZER_PROBE=") + probe + " " + self);
    EXPECT_EQ(result.exit_code, 86)
        << "a sanitizer finding must exit 86 (make sanitize-test sets ASAN_OPTIONS=exitcode=86, "
           "LSAN_OPTIONS=exitcode=86 and UBSAN_OPTIONS=halt_on_error=1:exitcode=86); got "
        << result.exit_code << ":\n"
        << result.output.substr(0, 2000);
    EXPECT_NE(result.output.find(std::string(probe) == "leak" ? "LeakSanitizer" : "runtime error"),
              std::string::npos)
        << result.output.substr(0, 2000);
  }
#endif
}

}  // namespace
}  // namespace syn::testing
