// libFuzzer target for the intermediate HDF5 readers every stage uses on its inputs: markers, motion,
// segments, synergies and library files. Any bytes either read or raise a DataError naming the file;
// nothing else may escape, crash, leak or hang. (libhdf5 itself is not instrumented, so coverage guides
// the mutations through our readers only.)
#include <cstddef>
#include <cstdint>
#include <string>

#include "common/error.h"
#include "common/library_file.h"
#include "common/markers_file.h"
#include "common/motion_file.h"
#include "common/segments_file.h"
#include "common/synergies_file.h"
#include "tests/fuzz/fuzz_input_file.h"

namespace {

template <typename Read>
void Try(Read read) {
  try {
    read();
  } catch (const syn::DataError&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  const std::string path = syn::fuzzing::WriteFuzzInput(data, size, "intermediate.h5");
  Try([&] { (void)syn::ReadMarkersFile(path); });
  Try([&] { (void)syn::ReadMotionFile(path); });
  Try([&] { (void)syn::ReadSegmentsFile(path); });
  Try([&] {
    syn::SynergyLabels labels;
    (void)syn::ReadTrialSynergies(path, &labels);
  });
  Try([&] {
    const syn::LibraryReader library(path);
    for (const std::string& name : library.synergyNames()) (void)library.read(name);
    for (const std::string& style : library.styleNames()) (void)library.styleBasis(style);
  });
  return 0;
}
