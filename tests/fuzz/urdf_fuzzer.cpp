// libFuzzer target for the URDF parser and the floating-root rule (a massless root link whose only joint
// is floating is the free base): any bytes either parse or raise a DataError; nothing else may escape,
// crash or hang.
#include <cstddef>
#include <cstdint>
#include <string>

#include "common/error.h"
#include "common/urdf.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  try {
    syn::RobotDescription description = syn::ParseUrdf(std::string(reinterpret_cast<const char*>(data), size), "fuzz.urdf");
    syn::RobotDescription welded = description;
    (void)syn::TakeFloatingRootJointAsFreeBase(description);
    (void)syn::WeldFloatingRootJoint(welded);
    // The free base's child must still be the one root, with every remaining joint's links present.
    if (description.root_link < 0 || description.root_link >= static_cast<int>(description.links.size())) __builtin_trap();
    for (const syn::UrdfJoint& joint : description.joints) {
      if (description.findLink(joint.parent) < 0 || description.findLink(joint.child) < 0) __builtin_trap();
    }
  } catch (const syn::DataError&) {
  }
  return 0;
}
