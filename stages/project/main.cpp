// syn-project IN.motion.h5 --library L.h5 [--style NAME] [--torso-motion T.motion.h5] -o OUT.motion.h5.
// Its before/after metrics come from syn-evaluate on both files (`make project`).
#include <iostream>
#include <optional>

#include "common/cli.h"
#include "common/intermediate_file.h"
#include "common/library_file.h"
#include "common/robot_map.h"
#include "stages/project/projection.h"

int main(int argc, char** argv) {
  CLI::App app{"Project a retargeted motion (e.g. text-to-motion output) into a style's synergy subspace through "
               "the upper-torso null space: u = S S' N_t u_in + u_t, N_t = I - Jbar_t J_t the dynamically "
               "consistent null space of the torso orientation task, u_t the torso motion from the library (the "
               "torso part of the library's reconstruction of the input, or of a composed motion: syn-compose "
               "a script, then --torso-motion). Evaluate both files with syn-evaluate for foot sliding and power "
               "before and after (make project does).",
               "syn-project"};
  syn::CommonFlags common;
  syn::AddCommonFlags(app, common);
  std::string input, library_path, style, torso_motion_path, model_path, robot_map_path, floating_base = "auto";
  app.add_option("INPUT", input, "Retargeted motion")->required();
  app.add_option("--library", library_path, "Synergy library (syn-library)")->required();
  app.add_option("--style", style, "The style whose shared basis S is used (default: the library's only style)");
  app.add_option("--torso-motion", torso_motion_path,
                 "A motion on the same robot (e.g. syn-compose output) whose velocities give the torso motion u_t");
  app.add_option("--model", model_path, "The robot URDF of the motion")->required();
  app.add_option("--robot-map", robot_map_path, "Robot map: the upper_torso task's link")->required();
  app.add_option("--floating-base", floating_base, "auto | free | fixed, as for syn-retarget")->capture_default_str();
  return syn::RunTool(app, argc, argv, [&] {
    const syn::Model model = syn::LoadModel(model_path, floating_base);
    syn::PrintWarnings("syn-project", model.warnings());
    syn::PrintNotes("syn-project", model.notes(), common.verbose);
    const syn::RobotMap map = syn::LoadRobotMap(robot_map_path);
    int torso_link = -1;
    for (const syn::RobotTask& task : map.tasks) {
      if (task.landmark != "upper_torso") continue;
      torso_link = model.findLinkIndex(task.link);
      if (torso_link < 0) {
        throw syn::DataError(syn::Location::AtLine(map.file, task.line), "link '" + task.link + "' is not in " + model.name());
      }
    }
    if (torso_link < 0) throw syn::DataError(syn::Location::InFile(map.file), "the robot map has no upper_torso task");
    const syn::LibraryReader library(library_path);
    if (style.empty()) {
      const std::vector<std::string> styles = library.styleNames();
      if (styles.size() != 1) {
        std::string known;
        for (const std::string& s : styles) known += (known.empty() ? "" : ", ") + s;
        throw syn::UsageError("the library holds several styles (" + known + "): choose one with --style");
      }
      style = styles.front();
    }
    const Eigen::MatrixXd basis = library.styleBasis(style);
    const syn::MotionData motion = syn::ReadMotionFile(input);
    std::optional<syn::MotionData> torso_motion;
    if (!torso_motion_path.empty()) {
      torso_motion = syn::ReadMotionFile(torso_motion_path);
      syn::CheckMotionMatchesModel(*torso_motion, model);
    }
    const syn::ProjectionResult result =
        syn::ProjectMotion(motion, model, torso_link, basis, torso_motion ? &*torso_motion : nullptr);

    syn::Provenance provenance;
    provenance.schema = syn::kMotionSchema;
    provenance.schema_version = syn::kMotionSchemaVersion;
    provenance.producer = std::string("syn-project ") + syn::kVersion;
    provenance.parameters = {{"style", style}, {"floating_base", floating_base}};
    provenance.inputs = nlohmann::json::array({syn::DescribeInput(input), syn::DescribeInput(library_path),
                                               syn::DescribeInput(model_path), syn::DescribeInput(robot_map_path)});
    if (!torso_motion_path.empty()) provenance.inputs.push_back(syn::DescribeInput(torso_motion_path));
    syn::IntermediateWriter writer(common.output, provenance);
    syn::WriteMotionData(writer, result.motion);
    writer.commit();

    std::cerr << "syn-project: " << input << " -> " << common.output << " (style " << style << ", "
              << basis.rows() << " synergies); worst |J_t N_t u|/|J_t||u| " << result.worst_task_leak
              << ", worst subspace residual " << result.worst_subspace_residual << "\n";
  });
}
