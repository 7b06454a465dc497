// libFuzzer target for the c3d reader and the normalisation after it: any bytes either parse or
// raise a DataError; nothing else may escape, crash or hang.
#include <cstddef>
#include <cstdint>
#include <string_view>

#include "common/error.h"
#include "common/intermediate_file.h"
#include "stages/ingest/capture_normalization.h"
#include "stages/ingest/c3d_reader.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    syn::MarkerData capture = syn::ParseC3d(data, size, "fuzz.c3d");
    (void)syn::ParseC3dParameters(data, size, "fuzz.c3d");
    // What syn-ingest does next: text made UTF-8, the up axis decided from the data, and the metadata
    // dumped as JSON. None of it may throw anything but a DataError (no json type_error for a stray byte).
    syn::NormalizeCapture(capture, {});
    (void)syn::CanonicalJson(capture.metadata);
    (void)syn::CanonicalJson(nlohmann::json(capture.labels));
  } catch (const syn::DataError&) {
  }
  return 0;
}
