// syn-compose SCRIPT.toml --library L.h5 -o OUT.motion.h5: a motion scripted from library synergies.
#include <iostream>

#include "common/cli.h"
#include "common/intermediate_file.h"
#include "common/motion_file.h"
#include "stages/compose/composer.h"

int main(int argc, char** argv) {
  CLI::App app{"Compose a motion from a script of library synergies (manifests/scripts/README.md): each step plays "
               "one segment's synergies with constant or keyframed coefficients, a duration (a tempo change keeps "
               "the displacement) and repetitions, cross-fading into the next step with step, linear, cubic or "
               "minimum-jerk interpolation, integrated from where the previous step ended. A step that would "
               "leave a joint's position or velocity limits is scaled down, with a warning naming it.",
               "syn-compose"};
  syn::CommonFlags common;
  syn::AddCommonFlags(app, common);
  std::string script_path, library_path;
  app.add_option("SCRIPT", script_path, "Compose script (TOML)")->required();
  app.add_option("--library", library_path, "Synergy library (syn-library)")->required();
  return syn::RunTool(app, argc, argv, [&] {
    const syn::ComposeScript script = syn::LoadComposeScript(script_path);
    const syn::Model model = syn::LoadModel(script.model, script.floating_base);
    syn::PrintWarnings("syn-compose", model.warnings());
    syn::PrintNotes("syn-compose", model.notes(), common.verbose);
    const syn::LibraryReader library(library_path);
    const syn::Composer composer(script, library, model, syn::Composer::StartPose(script, library));
    const syn::ComposedMotion composed = composer.compose();
    for (const std::string& warning : composed.warnings) std::cerr << "syn-compose: warning: " << warning << "\n";

    syn::Provenance provenance;
    provenance.schema = syn::kMotionSchema;
    provenance.schema_version = syn::kMotionSchemaVersion;
    provenance.producer = std::string("syn-compose ") + syn::kVersion;
    provenance.parameters = {{"warnings", composed.warnings}};
    provenance.inputs = nlohmann::json::array(
        {syn::DescribeInput(script_path), syn::DescribeInput(library_path), syn::DescribeInput(script.model)});
    syn::IntermediateWriter writer(common.output, provenance);
    syn::WriteMotionData(writer, composed.motion);
    writer.commit();
    std::cerr << "syn-compose: " << script_path << " -> " << common.output << ": " << script.steps.size() << " steps, "
              << composed.motion.frames() << " frames, " << composed.motion.time_s.back() << " s\n";
  });
}
