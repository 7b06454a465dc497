#include "stages/inspect/describe_model.h"

#include <cmath>

#include "common/model.h"

namespace syn {

nlohmann::json DescribeModel(const std::string& urdf_path, const std::string& floating_base) {
  ModelOptions options;
  options.floating_base = FloatingBaseFromName(floating_base);
  const Model model = Model::Load(urdf_path, options);
  nlohmann::json joints = nlohmann::json::array();
  for (const ModelJoint& joint : model.joints()) {
    joints.push_back({{"name", joint.name}, {"type", joint.type}, {"parent", joint.parent}, {"child", joint.child},
                      {"q_index", joint.q_index}, {"u_index", joint.u_index}});
  }
  nlohmann::json limits = nlohmann::json::object();
  for (int i = 0; i < model.nq(); ++i) {
    if (std::isfinite(model.qLower()[i]) || std::isfinite(model.qUpper()[i])) {
      limits[model.coordinateNames()[static_cast<size_t>(i)]] = {model.qLower()[i], model.qUpper()[i]};
    }
  }
  return {{"file", urdf_path},
          {"name", model.name()},
          {"sha256", model.sourceSha256()},
          {"floating_base", std::string(FloatingBaseName(model.floatingBase()))},
          {"nq", model.nq()},
          {"nu", model.nu()},
          {"total_mass", model.totalMass()},
          {"coordinates", model.coordinateNames()},
          {"velocities", model.velocityNames()},
          {"limits", limits},
          {"links", model.linkNames()},
          {"joints", joints},
          {"warnings", model.warnings()},
          {"notes", model.notes()}};
}

}  // namespace syn
