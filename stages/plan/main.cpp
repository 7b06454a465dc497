// syn-plan MANIFEST -o outputs/NAME/rules.mk: turn a dataset manifest into
// make rules (see stages/plan/manifest.h for the manifest format).
#include <cstdlib>
#include <iostream>

#include "common/cli.h"
#include "stages/evaluate/evaluate.h"
#include "stages/ingest/ingest.h"
#include "stages/retarget/retarget.h"
#include "stages/segment/segmentation.h"
#include "stages/synergies/synergies.h"
#include "stages/plan/manifest.h"
#include "stages/plan/rules.h"

namespace {

// The parameters every stage accepts, from each stage's own options struct.
syn::StageParameterNames NamesOf(const std::string& stage, const nlohmann::json& defaults) {
  syn::StageParameterNames names{stage, {}};
  for (auto item = defaults.begin(); item != defaults.end(); ++item) names.names.push_back(item.key());
  return names;
}

// Labels (subject, trial, style, motion class) come from the trial, not from stage parameters.
syn::StageParameterNames SynergyParameterNames() {
  syn::StageParameterNames names = NamesOf("synergies", syn::SynergyOptions{}.ToJson());
  std::erase_if(names.names, [](const std::string& name) {
    return name == "subject" || name == "trial" || name == "style" || name == "motion_class";
  });
  return names;
}

std::vector<syn::StageParameterNames> KnownStages() {
  return {NamesOf("ingest", syn::IngestOptions{}.ToJson()), NamesOf("retarget", syn::RetargetOptions{}.ToJson()),
          NamesOf("segment", syn::SegmentOptions{}.ToJson()), SynergyParameterNames(),
          NamesOf("evaluate", syn::EvaluateOptions{}.ToJson()),
          syn::StageParameterNames{"library", {"components"}},
          // The subject for syn-human (stages/human/human_model.h), read by `make power-ratio`.
          syn::StageParameterNames{"human", {"height", "mass", "sex"}}};
}

}  // namespace

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
  app.add_option("MANIFEST", manifest_path, "Dataset manifest (TOML)")->required();
  app.add_option("--dataset-root", dataset_root, "Replace the manifest's root (default: $DATASET_ROOT if set)");
  app.add_option("--outputs", outputs_root, "Folder that receives outputs/<name>/")->capture_default_str();
  return syn::RunTool(app, argc, argv, [&] {
    if (dataset_root.empty() && std::getenv("DATASET_ROOT")) dataset_root = std::getenv("DATASET_ROOT");
    const syn::Manifest manifest = syn::LoadManifest(manifest_path, dataset_root, KnownStages());
    const syn::Plan plan = syn::MakePlan(manifest, outputs_root);
    const int rewritten = syn::WritePlan(plan, manifest, common.output);
    std::cerr << "syn-plan: " << manifest.name << ": " << manifest.trials.size() << " trials, " << plan.jobs.size()
              << " jobs; " << rewritten << " parameter stamps changed -> " << common.output << "\n";
  });
}
