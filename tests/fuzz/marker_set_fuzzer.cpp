// libFuzzer target for marker sets (manifests/markersets/*.toml, ParseMarkerSet): a marker set or a
// DataError at file:line; nothing else may escape, crash, leak or hang.
#include <cstddef>
#include <cstdint>
#include <string>

#include "common/error.h"
#include "common/marker_set.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    (void)syn::ParseMarkerSet(std::string(reinterpret_cast<const char*>(data), size), "fuzz.toml");
  } catch (const syn::DataError&) {
  }
  return 0;
}
