// syn-human --height H --mass M [--sex f|m] -o human.urdf [--robot-map-out human.toml]
#include <cmath>
#include <iostream>

#include "common/cli.h"
#include "common/file_bytes.h"
#include "common/markers_file.h"
#include "stages/human/capture_stature.h"
#include "stages/human/human_model.h"

int main(int argc, char** argv) {
  CLI::App app{"Write an anthropometric human model (URDF) for a subject of the given stature, mass and sex: "
               "segment masses, centres of mass and radii of gyration from de Leva (1996, J. Biomech. 29:1223, "
               "Table 4), lengths scaled by stature, joint ranges from OpenSim's full-body model; and its robot map "
               "for syn-retarget / syn-evaluate.",
               "syn-human"};
  syn::CommonFlags common;
  syn::AddCommonFlags(app, common);
  syn::HumanModelOptions options;
  std::string robot_map_out, height_from_markers;
  app.add_option("--height", options.height,
                 "Stature (m), [1, 2.5]; manifest [human] height. Default: de Leva's reference subject (1.741 m male, "
                 "1.735 m female), with a warning");
  app.add_option("--height-from-markers", height_from_markers,
                 "Measure the stature in a markers file (syn-ingest) instead: the vertical extent of its markers and "
                 "bodies in its calibration frame (a BVH's T-pose, kept by syn-ingest --drop-first-frame), else at the first "
                 "frame with data (head top to toe tips for BVH skeletons)")
      ->excludes("--height");
  app.add_option("--mass", options.mass,
                 "Body mass (kg), [20, 300]; manifest [human] mass. Default: de Leva's reference subject (73.0 kg "
                 "male, 61.9 kg female), with a warning");
  app.add_option("--sex", options.sex, "f | m: which column of de Leva's table; manifest [human] sex")
      ->capture_default_str();
  app.add_option("--name", options.name, "URDF robot name")->capture_default_str();
  app.add_option("--robot-map-out", robot_map_out, "Also write the model's robot map (TOML) here");
  return syn::RunTool(app, argc, argv, [&] {
    syn::HumanModelSummary summary;
    if (!height_from_markers.empty()) {
      const syn::CaptureStature stature = syn::StatureFromCapture(syn::ReadMarkersFile(height_from_markers), height_from_markers);
      options.height = stature.height;
      std::cerr << "syn-human: stature " << stature.height << " m from " << height_from_markers
                << (stature.frame < 0 ? std::string(" calibration frame") : " frame " + std::to_string(stature.frame))
                << "\n";
    }
    const syn::HumanModelFiles files = syn::BuildHumanModel(options, &summary);
    syn::PrintWarnings("syn-human", summary.warnings);
    syn::WriteFileAtomically(common.output, files.urdf);
    if (!robot_map_out.empty()) syn::WriteFileAtomically(robot_map_out, files.robot_map);
    std::cerr << "syn-human: " << summary.BriefReport() << " -> " << common.output
              << (robot_map_out.empty() ? "" : ", " + robot_map_out) << "\n";
  });
}
