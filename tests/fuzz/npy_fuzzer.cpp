// libFuzzer target for the npy reader: any bytes either parse or raise a
// DataError; nothing else may escape, crash or hang.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "common/error.h"
#include "stages/ingest/npy_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    (void)syn::HumanMl3dJointsToMarkerData(syn::ParseNpy(data, size, "fuzz.npy"), "fuzz.npy");
  } catch (const syn::DataError&) {
  }
  return 0;
}
