// syn-library IN.synergies.h5... -o library.h5 [--style NAME]: style-conditioned synergy libraries.
#include <iostream>

#include "common/cli.h"
#include "stages/library/style_library.h"

int main(int argc, char** argv) {
  CLI::App app{"Build style libraries from per-trial synergies: per style, a shared basis (PCA over all of its "
               "segments' centred velocity samples) and the variance it retains on each trial; per motion class, "
               "mean and standard deviation of the PC1-PC3 variance ratios across segments. Styles and classes are "
               "the labels syn-synergies stored (from the manifest).",
               "syn-library"};
  syn::CommonFlags common;
  syn::AddCommonFlags(app, common);
  std::vector<std::string> inputs;
  std::string only_style;
  int components = 3;
  app.add_option("INPUT", inputs, "Synergies files")->required();
  app.add_option("--style", only_style, "Keep only the trials of this style");
  app.add_option("--components", components, "Size of each style's shared basis")->capture_default_str();
  const auto parameters = [&] { return nlohmann::json{{"style", only_style}, {"components", components}}; };
  return syn::RunTool(app, argc, argv, parameters, [&] {
    if (components < 1) throw syn::UsageError("--components must be at least 1");
    std::vector<syn::LabelledTrial> trials;
    std::vector<std::string> sources;
    nlohmann::json described = nlohmann::json::array();
    for (const std::string& input : inputs) {
      syn::LabelledTrial trial;
      trial.synergies = syn::ReadTrialSynergies(input, &trial.labels);
      if (!only_style.empty() && trial.labels.style != only_style) continue;
      trials.push_back(std::move(trial));
      sources.push_back(input);
      described.push_back(syn::DescribeInput(input));
    }
    if (trials.empty()) throw syn::UsageError("no input trial has style '" + only_style + "'");
    const syn::SynergyLibrary library = syn::BuildLibrary(trials, sources, components);
    syn::Provenance provenance;
    provenance.schema = syn::kLibrarySchema;
    provenance.schema_version = syn::kLibrarySchemaVersion;
    provenance.producer = std::string("syn-library ") + syn::kVersion;
    provenance.parameters = parameters();
    provenance.inputs = described;
    syn::IntermediateWriter writer(common.output, provenance);
    syn::WriteLibrary(writer, library);
    writer.commit();
    for (const auto& [style, basis] : library.styles) {
      std::cerr << "syn-library: style " << style << ": " << basis.trials.size() << " trials, " << basis.segments
                << " segments, basis explains " << 100 * basis.explained_variance_ratio.sum() << " %\n";
    }
  });
}
