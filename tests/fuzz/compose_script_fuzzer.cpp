// libFuzzer target for compose scripts (manifests/scripts/*.toml, LoadComposeScript): a script or a
// DataError at script:line; nothing else may escape, crash, leak or hang.
#include <cstddef>
#include <cstdint>
#include <string>

#include "common/error.h"
#include "stages/compose/compose_script.h"
#include "tests/fuzz/fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = syn::fuzzing::WriteFuzzInput(data, size, "script.toml");
  try {
    (void)syn::LoadComposeScript(path);
  } catch (const syn::DataError&) {
  }
  return 0;
}
