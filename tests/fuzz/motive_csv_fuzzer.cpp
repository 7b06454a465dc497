// libFuzzer target for the motive_csv reader: any bytes either parse or raise a
// DataError; nothing else may escape, crash or hang.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "common/error.h"
#include "stages/ingest/motive_csv_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    (void)syn::ParseMotiveCsv(std::string_view(reinterpret_cast<const char*>(data), size), "fuzz.csv");
  } catch (const syn::DataError&) {
  }
  return 0;
}
