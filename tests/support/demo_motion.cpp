#include "tests/support/demo_motion.h"

#include <unistd.h>

#include <filesystem>
#include <map>
#include <memory>

#include "common/markers_file.h"
#include "stages/ingest/ingest.h"
#include "stages/retarget/retarget.h"
#include "tests/support/shared_data.h"

namespace syn::testing {

MotionData CmuBvhOnG1(const std::string& bvh_path) {
  const std::string dir = std::filesystem::temp_directory_path() / ("syn_demo_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  IngestOptions ingest;
  ingest.drop_first_frame = true;  // CMU's first frame is the T-pose (manifests/demo.toml)
  const MarkerData capture = IngestCapture(bvh_path, ingest, nullptr);
  const std::string markers = dir + "/capture.markers.h5";
  {
    IntermediateWriter writer(markers, {kMarkersSchema, kMarkersSchemaVersion, "test", {}, nlohmann::json::array()});
    WriteMarkerData(writer, capture);
    writer.commit();
  }
  RetargetOptions retarget;
  retarget.model = SourcePath(kG1Urdf);
  retarget.robot_map = SourcePath(kG1Map);
  retarget.markerset = SourcePath("manifests/markersets/cmu-bvh.toml");
  MotionData motion = RetargetFile(markers, retarget, nullptr);
  std::filesystem::remove_all(dir);
  return motion;
}

const MotionData& DemoMotionOnG1(const std::string& trial) {
  static std::map<std::string, std::unique_ptr<MotionData>> cache;
  std::unique_ptr<MotionData>& motion = cache[trial];
  if (!motion) motion = std::make_unique<MotionData>(CmuBvhOnG1(SourcePath("datasets/demo/" + trial + ".bvh")));
  return *motion;
}

}  // namespace syn::testing
