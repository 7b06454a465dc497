// libFuzzer target for the intermediate-file readers every stage uses on its inputs (markers, motion,
// segments, synergies, library): any content either reads or raises a DataError naming the file; nothing else
// may escape, crash, leak or hang.
//
// The input is not the file's bytes but a recipe for its content, written with the real writer into a valid
// HDF5 container: a schema, then datasets and attributes whose names come from what the readers look for
// (plus nonsense), with fuzzed ranks, shapes, types and values. Raw-byte mutation of HDF5 files crashes inside
// libhdf5's own parser within seconds (memcpy-param-overlap in libhdf5_serial 1.10), which is not code we can
// fix; what we own, and what this fuzzes, is every reader's trust in shapes, types, counts and indices.
#include <fuzzer/FuzzedDataProvider.h>

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "common/error.h"
#include "common/intermediate_file.h"
#include "common/library_file.h"
#include "common/markers_file.h"
#include "common/motion_file.h"
#include "common/segments_file.h"
#include "common/synergies_file.h"
#include "tests/fuzz/fuzz_input_file.h"

namespace {

const char* const kSchemas[] = {syn::kMarkersSchema, syn::kMotionSchema, syn::kSegmentsSchema, syn::kSynergiesSchema,
                                syn::kLibrarySchema, "synsculpt.other"};

// What the readers open (common/*_file.cpp), and a few names they do not.
const char* const kNames[] = {
    "time", "points", "labels", "bodies", "body_parents", "body_pose", "calibration_body_pose", "analog", "analog_labels", "analog_units",
    "computed_points", "computed_labels", "computed_kinds", "event_times", "event_labels", "event_contexts", "q", "u",
    "udot", "tau", "coordinate_names", "velocity_names", "landmark_names", "landmark_targets", "landmark_error",
    "analysis_time", "delta_p", "boundaries", "boundary_reasons", "style_names", "trial_names", "class_names",
    "segments/000/components", "segments/000/singular_values", "segments/000/scores", "segments/000/mean_u",
    "segments/000/times", "segments/000/explained_variance_ratio", "segments/001/components",
    "styles/a/components", "styles/a/trials", "styles/a/pc_ratio_mean", "styles/a/pc_ratio_std",
    "styles/a/trial_retained_variance", "styles/a/velocities", "trials/a/t/000/components", "trials/a/t/000/times",
    "trials/a/t/000/mean_u", "classes/a/components", "segments", "nonsense"};
const char* const kAttributes[] = {"rate_hz", "analog_rate_hz", "metadata", "warnings", "model_name", "model_sha256",
                                   "total_mass", "segment_count", "threshold_used", "analysis_rate", "start_frame",
                                   "end_frame", "duration", "subject", "trial", "style", "motion_class"};

void WriteRecipe(FuzzedDataProvider& recipe, const std::string& path) {
  syn::Provenance provenance;
  provenance.schema = recipe.PickValueInArray(kSchemas);
  provenance.schema_version = recipe.ConsumeBool() ? 1 : recipe.ConsumeIntegral<int64_t>();
  provenance.producer = "fuzz";
  syn::IntermediateWriter writer(path, provenance);
  std::vector<std::string> written;
  const int datasets = recipe.ConsumeIntegralInRange(0, 24);
  for (int d = 0; d < datasets && recipe.remaining_bytes() > 0; ++d) {
    const std::string name = recipe.PickValueInArray(kNames);
    bool taken = false;
    // A name is free when it is neither written nor under or above a written one (a dataset cannot be a group).
    for (const std::string& other : written) {
      taken = taken || other == name || name.rfind(other + "/", 0) == 0 || other.rfind(name + "/", 0) == 0;
    }
    if (taken) continue;
    std::vector<int64_t> dims(static_cast<size_t>(recipe.ConsumeIntegralInRange(0, 3)));
    int64_t count = 1;
    for (int64_t& dim : dims) {
      dim = recipe.ConsumeIntegralInRange<int64_t>(0, 8);
      count *= dim;
    }
    switch (recipe.ConsumeIntegralInRange(0, 2)) {
      case 0: {
        std::vector<double> values(static_cast<size_t>(count));
        for (double& value : values) value = recipe.ConsumeFloatingPoint<double>();
        writer.writeDoubles(name, dims, values.data());
        break;
      }
      case 1: {
        std::vector<int64_t> values(static_cast<size_t>(count));
        for (int64_t& value : values) value = recipe.ConsumeIntegralInRange<int64_t>(-3, 40);
        writer.writeInts(name, dims, values.data());
        break;
      }
      default: {
        std::vector<std::string> values(static_cast<size_t>(recipe.ConsumeIntegralInRange(0, 8)));
        for (std::string& value : values) value = recipe.ConsumeRandomLengthString(16);
        writer.writeStrings(name, values);
      }
    }
    written.push_back(name);
  }
  const int attributes = recipe.ConsumeIntegralInRange(0, 12);
  for (int a = 0; a < attributes && recipe.remaining_bytes() > 0; ++a) {
    const std::string object = written.empty() || recipe.ConsumeBool() ? "" : recipe.PickValueInArray(kNames);
    bool exists = object.empty();
    for (const std::string& name : written) exists = exists || name == object;
    if (!exists) continue;
    const std::string name = recipe.PickValueInArray(kAttributes);
    switch (recipe.ConsumeIntegralInRange(0, 2)) {
      case 0: writer.writeAttribute(object, name, recipe.ConsumeFloatingPoint<double>()); break;
      case 1: writer.writeAttribute(object, name, recipe.ConsumeIntegralInRange<int64_t>(-3, 40)); break;
      default: writer.writeAttribute(object, name, recipe.ConsumeRandomLengthString(32));
    }
  }
  writer.commit();
}

template <typename Read>
void Try(Read read) {
  try {
    read();
  } catch (const syn::DataError&) {
  }
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  FuzzedDataProvider recipe(data, size);
  const std::string path = syn::fuzzing::WriteFuzzInput(nullptr, 0, "intermediate.h5");
  WriteRecipe(recipe, path);
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
