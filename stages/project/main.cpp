// syn-project IN.motion.h5 --library L.h5 [--style NAME] [--torso-script T.toml] -o OUT.motion.h5.
#include <iostream>

#include "common/cli.h"
#include "common/intermediate_file.h"
#include "stages/compose/composer.h"
#include "stages/evaluate/evaluate.h"
#include "stages/library/style_library.h"
#include "stages/project/projection.h"
#include "stages/retarget/robot_map.h"

int main(int argc, char** argv) {
  CLI::App app{"Project a retargeted motion (e.g. text-to-motion output) into a style's synergy subspace through "
               "the upper-torso null space: u = S S' N_t u_in + u_t, N_t = I - Jbar_t J_t the dynamically "
               "consistent null space of the torso orientation task, u_t the torso motion from the library (the "
               "torso part of the library's reconstruction of the input, or of a compose script). Prints foot "
               "sliding and mean power before and after.",
               "syn-project"};
  syn::CommonFlags common;
  syn::AddCommonFlags(app, common);
  std::string input, library_path, style, torso_script, model_path, robot_map_path, floating_base = "auto";
  syn::EvaluateOptions evaluation;
  evaluation.monte_carlo.samples = 0;
  app.add_option("INPUT", input, "Retargeted motion")->required();
  app.add_option("--library", library_path, "Synergy library (syn-library)")->required();
  app.add_option("--style", style, "The style whose shared basis S is used (default: the library's only style)");
  app.add_option("--torso-script", torso_script, "Compose script whose motion gives the torso velocity u_t");
  app.add_option("--model", model_path, "The robot URDF of the motion")->required();
  app.add_option("--robot-map", robot_map_path, "Robot map: the upper_torso task's link and the feet")->required();
  app.add_option("--floating-base", floating_base, "auto | free | fixed, as for syn-retarget")->capture_default_str();
  app.add_option("--eval-rate", evaluation.eval_rate, "Rate of the before/after evaluation, Hz")->capture_default_str();
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
    if (!torso_script.empty()) {
      const syn::ComposeScript script = syn::LoadComposeScript(torso_script);
      const syn::Composer composer(script, library, model, syn::Composer::StartPose(script, library));
      const syn::ComposedMotion composed = composer.compose();
      for (const std::string& warning : composed.warnings) std::cerr << "syn-project: torso script: warning: " << warning << "\n";
      torso_motion = composed.motion;
    }
    const syn::ProjectionResult result =
        syn::ProjectMotion(motion, model, torso_link, basis, torso_motion ? &*torso_motion : nullptr);

    syn::Provenance provenance;
    provenance.schema = syn::kMotionSchema;
    provenance.schema_version = syn::kMotionSchemaVersion;
    provenance.producer = std::string("syn-project ") + syn::kVersion;
    provenance.parameters = {{"style", style}, {"torso_script", torso_script}, {"floating_base", floating_base}};
    provenance.inputs = nlohmann::json::array({syn::DescribeInput(input), syn::DescribeInput(library_path),
                                               syn::DescribeInput(model_path), syn::DescribeInput(robot_map_path)});
    if (!torso_script.empty()) provenance.inputs.push_back(syn::DescribeInput(torso_script));
    syn::IntermediateWriter writer(common.output, provenance);
    syn::WriteMotionData(writer, result.motion);
    writer.commit();

    const std::vector<syn::FootPoints> feet = syn::FeetOnModel(map, model);
    const nlohmann::json before = syn::EvaluateMotion(motion, model, feet, nullptr, evaluation, "")["trial"];
    const nlohmann::json after = syn::EvaluateMotion(result.motion, model, feet, nullptr, evaluation, "")["trial"];
    std::cerr << "syn-project: " << input << " -> " << common.output << " (style " << style << ", "
              << basis.rows() << " synergies); worst |J_t N_t u|/|J_t||u| " << result.worst_task_leak
              << ", worst subspace residual " << result.worst_subspace_residual << "\n"
              << "                 before      after\n"
              << "foot sliding     " << before["foot_sliding_ratio"] << "  " << after["foot_sliding_ratio"] << "\n"
              << "power (W/kg)     " << before["mean_power_w_per_kg"] << "  " << after["mean_power_w_per_kg"] << "\n";
  });
}
