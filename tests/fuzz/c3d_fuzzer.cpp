// libFuzzer target for the c3d reader: any bytes either parse or raise a
// DataError; nothing else may escape, crash or hang.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "common/error.h"
#include "stages/ingest/c3d_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    (void)syn::ParseC3d(data, size, "fuzz.c3d");
  } catch (const syn::DataError&) {
  }
  return 0;
}
