#include "stages/inspect/describe_model.h"

#include "common/error.h"

namespace syn {

// TEMPORARY until common/model.h lands.
nlohmann::json DescribeModel(const std::string& urdf_path, const std::string&) {
  throw DataError(Location::InFile(urdf_path), "model loading not integrated yet");
}

}  // namespace syn
