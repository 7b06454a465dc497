// libFuzzer target for the URDF reader (ParseUrdf): any bytes either describe a robot or raise a DataError
// at file:line; nothing else may escape, crash, leak or hang.
#include <cstddef>
#include <cstdint>
#include <string>

#include "common/error.h"
#include "common/urdf.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    (void)syn::ParseUrdf(std::string(reinterpret_cast<const char*>(data), size), "fuzz.urdf");
  } catch (const syn::DataError&) {
  }
  return 0;
}
