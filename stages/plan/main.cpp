// syn-plan MANIFEST -o outputs/NAME/rules.mk: turn a dataset manifest into
// make rules (see stages/plan/manifest.h for the manifest format).
#include <cstdlib>
#include <iostream>

#include "common/cli.h"
#include "stages/plan/manifest.h"
#include "stages/plan/rules.h"
#include "stages/plan/stage_parameters.h"

int main(int argc, char** argv) {
  CLI::App app{"Check a dataset manifest and write the make rules that run every stage on every trial. "
               "Parameter stamp files are rewritten only when their content changes, so make re-runs exactly "
               "what a change affects.",
               "syn-plan"};
  syn::CommonFlags common;
  syn::AddCommonFlags(app, common);
  std::string manifest_path;
  std::string dataset_root;
  std::string outputs_root = "outputs";
  std::string stage_bin = syn::OwnExecutableFolder();
  app.add_option("MANIFEST", manifest_path, "Dataset manifest (TOML)")->required();
  app.add_option("--dataset-root", dataset_root, "Replace the manifest's root (default: $DATASET_ROOT if set)");
  app.add_option("--outputs", outputs_root, "Folder that receives outputs/<name>/")->capture_default_str();
  app.add_option("--stage-bin", stage_bin,
                 "Folder of the syn-* tools whose --print-parameters define each stage's parameters (default: "
                 "syn-plan's own folder)");
  return syn::RunTool(app, argc, argv, [&] {
    if (dataset_root.empty() && std::getenv("DATASET_ROOT")) dataset_root = std::getenv("DATASET_ROOT");
    const syn::Manifest manifest = syn::LoadManifest(manifest_path, dataset_root, syn::QueryStageParameters(stage_bin));
    syn::CheckParameterValues(manifest, stage_bin);
    // A capture without a licence can still be run; the release datasheet then says "unknown".
    for (const std::string& warning : manifest.release.licenceWarnings()) std::cerr << "syn-plan: warning: " << warning << "\n";
    const syn::Plan plan = syn::MakePlan(manifest, outputs_root);
    const int rewritten = syn::WritePlan(plan, manifest, common.output);
    std::cerr << "syn-plan: " << manifest.name << ": " << manifest.trials.size() << " trials, " << plan.jobs.size()
              << " jobs; " << rewritten << " parameter stamps changed -> " << common.output << "\n";
  });
}
