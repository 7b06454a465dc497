// libFuzzer target for dataset manifests (LoadManifest, what syn-plan reads): a manifest or a DataError at
// manifest:line; nothing else may escape, crash, leak or hang. The stage parameter names are a fixed
// sample here (syn-plan asks the built tools for them, which a fuzzer cannot).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "common/error.h"
#include "stages/plan/manifest.h"
#include "tests/fuzz/fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const std::vector<syn::StageParameterNames> kStages = {
      {"ingest", {"format", "up_axis", "units", "fill_gaps", "rate", "strip_prefix", "bvh_scale", "drop_first_frame"}},
      {"retarget", {"floating_base", "posture_scale"}},
      {"segment", {"threshold"}},
      {"evaluate", {"samples"}}};
  const std::string path = syn::fuzzing::WriteFuzzInput(data, size, "manifest.toml");
  try {
    (void)syn::LoadManifest(path, "", kStages);
  } catch (const syn::DataError&) {
  }
  return 0;
}
