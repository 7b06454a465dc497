// libFuzzer target for robot CSV motions (ReadRobotCsv, what syn-export reads back) on the bundled G1:
// poses or a DataError at file:line; nothing else may escape, crash, leak or hang.
#include <cstddef>
#include <cstdint>
#include <string>

#include "common/error.h"
#include "common/model.h"
#include "stages/export/motion_export.h"
#include "tests/fuzz/fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const syn::Model model =
      syn::Model::Load(std::string(SYN_SOURCE_DIR) + "/datasets/robots/unitree_g1/g1_29dof.urdf");
  const std::string path = syn::fuzzing::WriteFuzzInput(data, size, "motion.csv");
  try {
    (void)syn::ReadRobotCsv(path, model, 30.0);
  } catch (const syn::DataError&) {
  }
  return 0;
}
