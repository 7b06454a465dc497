// syn-synergies IN.motion.h5 IN.segments.h5 -o OUT.synergies.h5: PCA synergies per segment.
#include <iostream>

#include "common/cli.h"
#include "common/segments_file.h"
#include "stages/synergies/synergies.h"

int main(int argc, char** argv) {
  CLI::App app{"Per segment, centred PCA of the generalized velocities (X - mean = U S V^T): synergy directions V_i, "
               "coefficients a_i = sigma_i, profiles U_i(t); stores q0, the mean, the first --components synergies, "
               "their explained-variance ratios and the number of components reaching 90 %. Follows the paper's "
               "text (velocities), not its public code (joint positions).",
               "syn-synergies"};
  syn::CommonFlags common;
  syn::AddCommonFlags(app, common);
  syn::SynergyOptions options;
  std::string motion_path, segments_path;
  app.add_option("MOTION", motion_path, "Motion file")->required();
  app.add_option("SEGMENTS", segments_path, "Segments file (syn-segment)")->required();
  app.add_option("--components", options.components, "Synergies kept per segment (paper: 3)")->capture_default_str();
  app.add_option("--velocities", options.velocities,
                 "all (free-base velocities in the pelvis heading frame) | joints")
      ->transform(CLI::CheckedTransformer(
          std::map<std::string, syn::VelocitySet>{{"all", syn::VelocitySet::kAll}, {"joints", syn::VelocitySet::kJoints}}))
      ->default_str("all");
  app.add_option("--subject", options.labels.subject, "Label: subject");
  app.add_option("--trial", options.labels.trial, "Label: trial id");
  app.add_option("--style", options.labels.style, "Label: style library the trial joins");
  app.add_option("--motion-class", options.labels.motion_class, "Label: motion class");
  return syn::RunTool(app, argc, argv, [&] {
        syn::RequireValid(options);
        return options.ToJson();
      }, [&] {
    syn::RequireValid(options);
    const syn::MotionData motion = syn::ReadMotionFile(motion_path);
    const syn::SegmentsData segments = syn::ReadSegmentsFile(segments_path);
    const syn::TrialSynergies synergies = syn::ComputeTrialSynergies(motion, segments.boundaries, options);
    syn::Provenance provenance;
    provenance.schema = syn::kSynergiesSchema;
    provenance.schema_version = syn::kSynergiesSchemaVersion;
    provenance.producer = std::string("syn-synergies ") + syn::kVersion;
    provenance.parameters = options.ToJson();
    provenance.inputs = nlohmann::json::array({syn::DescribeInput(motion_path), syn::DescribeInput(segments_path)});
    syn::IntermediateWriter writer(common.output, provenance);
    syn::WriteTrialSynergies(writer, synergies, options.labels);
    writer.commit();
    double three = 0;
    for (const auto& segment : synergies.segments) three += segment.synergies.explained_variance_ratio.sum();
    std::cerr << "syn-synergies: " << motion_path << " -> " << common.output << ": " << synergies.segments.size()
              << " segments, mean variance explained by " << options.components << " synergies "
              << (synergies.segments.empty() ? 0.0 : 100.0 * three / static_cast<double>(synergies.segments.size())) << " %\n";
  });
}
