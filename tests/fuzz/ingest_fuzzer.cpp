// libFuzzer target for the whole ingest path, as syn-ingest runs it: format detection from the first bytes,
// the reader, unit/axis normalisation and cubic gap filling (IngestCapture). The first input byte picks the
// options (gap length, prefix stripping, first-frame drop, the file's extension); the rest is the file.
// Any bytes either give markers or raise a DataError; nothing else may escape, crash, leak or hang.
#include <cstddef>
#include <cstdint>

#include "common/error.h"
#include "stages/ingest/ingest.h"
#include "tests/fuzz/fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  if (size < 1) return 0;
  const uint8_t choice = data[0];
  static const char* const kExtensions[] = {"c3d", "trc", "csv", "bvh"};
  const std::string path =
      syn::fuzzing::WriteFuzzInput(data + 1, size - 1, std::string("capture.") + kExtensions[choice >> 6]);
  syn::IngestOptions options;
  options.fill_gaps = choice & 15;
  options.strip_prefix = (choice & 16) != 0;
  options.drop_first_frame = (choice & 32) != 0;
  syn::IngestSummary summary;
  try {
    (void)syn::IngestCapture(path, options, &summary);
  } catch (const syn::DataError&) {
  }
  return 0;
}
