#include "common/motion_file.h"

#include <algorithm>

#include "common/error.h"
#include "common/model.h"

namespace syn {

void WriteMotionData(IntermediateWriter& writer, const MotionData& motion) {
  const int64_t frames = motion.frames();
  writer.writeDoubles("time", motion.time_s);
  writer.writeStrings("coordinate_names", motion.coordinate_names);
  writer.writeStrings("velocity_names", motion.velocity_names);
  writer.writeDoubles("q", {frames, motion.nq()}, motion.q.data());
  writer.writeDoubles("u", {frames, motion.nu()}, motion.u.data());
  writer.writeDoubles("udot", {frames, motion.nu()}, motion.udot.data());
  writer.writeDoubles("tau", {frames, motion.nu()}, motion.tau.data());
  if (!motion.landmark_names.empty()) {
    const int64_t landmarks = static_cast<int64_t>(motion.landmark_names.size());
    writer.writeStrings("landmark_names", motion.landmark_names);
    writer.writeDoubles("landmark_targets", {frames, landmarks, 7}, motion.landmark_targets.data());
    writer.writeDoubles("landmark_error", {frames, landmarks, 2}, motion.landmark_error.data());
  }
  if (!motion.contact_feet.empty()) {
    writer.writeStrings("contact_feet", motion.contact_feet);
    writer.writeInts("contact", {frames, static_cast<int64_t>(motion.contact_feet.size())}, motion.contact.data());
    if (!motion.contact_force.empty()) {
      writer.writeDoubles("contact_force", {frames, static_cast<int64_t>(motion.contact_feet.size()), 3},
                          motion.contact_force.data());
      writer.writeDoubles("unexplained_wrench", {frames, 6}, motion.unexplained_wrench.data());
    }
  }
  writer.writeAttribute("", "model_name", motion.model_name);
  writer.writeAttribute("", "model_sha256", motion.model_sha256);
  writer.writeAttribute("", "total_mass", motion.total_mass);
}

void KeepFirstFrames(MotionData& motion, int64_t frames) {
  const size_t total = static_cast<size_t>(motion.frames()), kept = static_cast<size_t>(std::clamp<int64_t>(frames, 0, motion.frames()));
  if (total == 0) return;
  // Each array's entries per frame from its size: the optional ones may be empty.
  const auto keep = [&](auto& values) { values.resize(values.size() / total * kept); };
  keep(motion.q), keep(motion.u), keep(motion.udot), keep(motion.tau);
  keep(motion.landmark_targets), keep(motion.landmark_error);
  keep(motion.contact), keep(motion.contact_force), keep(motion.unexplained_wrench);
  motion.time_s.resize(kept);
}

MotionData ReadMotionFile(const std::string& path) {
  IntermediateReader reader(path, kMotionSchema, kMotionSchemaVersion);
  MotionData motion;
  motion.time_s = reader.readDoubles("time").values;
  motion.coordinate_names = reader.readStrings("coordinate_names");
  motion.velocity_names = reader.readStrings("velocity_names");
  const auto read = [&](const char* name, int64_t width, std::vector<double>& into) {
    DoubleArray array = reader.readDoubles(name);
    if (array.dims.size() != 2 || array.dims[0] != motion.frames() || array.dims[1] != width) {
      throw DataError(Location::InFile(path), std::string("dataset '") + name + "' should be [" +
                                                 std::to_string(motion.frames()) + ", " + std::to_string(width) + "]");
    }
    into = std::move(array.values);
  };
  read("q", motion.nq(), motion.q);
  read("u", motion.nu(), motion.u);
  read("udot", motion.nu(), motion.udot);
  read("tau", motion.nu(), motion.tau);
  if (reader.has("landmark_names")) {
    motion.landmark_names = reader.readStrings("landmark_names");
    motion.landmark_targets = reader.readDoubles("landmark_targets").values;
    motion.landmark_error = reader.readDoubles("landmark_error").values;
  }
  if (reader.has("contact_feet")) {
    motion.contact_feet = reader.readStrings("contact_feet");
    motion.contact = reader.readInts("contact");
    if (motion.contact.size() != static_cast<size_t>(motion.frames()) * motion.contact_feet.size()) {
      throw DataError(Location::InFile(path), "dataset 'contact' should be [" + std::to_string(motion.frames()) + ", " +
                                                  std::to_string(motion.contact_feet.size()) + "]");
    }
    if (reader.has("contact_force")) {
      motion.contact_force = reader.readDoubles("contact_force").values;
      motion.unexplained_wrench = reader.readDoubles("unexplained_wrench").values;
      if (motion.contact_force.size() != static_cast<size_t>(motion.frames()) * motion.contact_feet.size() * 3 ||
          motion.unexplained_wrench.size() != static_cast<size_t>(motion.frames()) * 6) {
        throw DataError(Location::InFile(path), "datasets 'contact_force' and 'unexplained_wrench' should be [" +
                                                    std::to_string(motion.frames()) + ", feet, 3] and [" +
                                                    std::to_string(motion.frames()) + ", 6]");
      }
    }
  }
  motion.model_name = reader.readStringAttribute("", "model_name");
  motion.model_sha256 = reader.readStringAttribute("", "model_sha256");
  motion.total_mass = reader.readDoubleAttribute("", "total_mass");
  return motion;
}

void CheckMotionMatchesModel(const MotionData& motion, const Model& model) {
  if (!motion.model_sha256.empty() && motion.model_sha256 != model.sourceSha256()) {
    throw DataError(Location::InFile(model.sourcePath()),
                    "this URDF is not the model the motion was made with (" + motion.model_name + ", SHA-256 " +
                        motion.model_sha256.substr(0, 12) + "...)");
  }
  if (motion.nq() != model.nq() || motion.nu() != model.nu()) {
    throw DataError(Location::InFile(model.sourcePath()), "the motion's coordinates do not match the model's");
  }
}

}  // namespace syn
