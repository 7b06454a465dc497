// syn-segment IN.motion.h5 --model ROBOT.urdf -o OUT.segments.h5: momentum segmentation.
#include <iostream>

#include "common/cli.h"
#include "common/intermediate_file.h"
#include "common/motion_file.h"
#include "stages/segment/segmentation.h"

int main(int argc, char** argv) {
  CLI::App app{"Split a motion into primitives where the generalized momentum p = A(q)u jumps: resampled to the "
               "analysis rate, dP(t_i) = |p(t_i) - p(t_(i-1))|, a boundary where dP exceeds the threshold and at "
               "least --min-duration after the previous one. The threshold's meaning depends on the robot's mass "
               "and on the analysis rate; --threshold-quantile gives a scale-free alternative.",
               "syn-segment"};
  syn::CommonFlags common;
  syn::AddCommonFlags(app, common);
  syn::SegmentOptions options;
  std::string input, model_path, floating_base = "auto";
  app.add_option("INPUT", input, "Motion file (syn-retarget, syn-compose or syn-project)")->required();
  app.add_option("--model", model_path, "The robot URDF the motion was made with")->required();
  app.add_option("--floating-base", floating_base, "auto | free | fixed, as for syn-retarget")->capture_default_str();
  app.add_option("--threshold", options.threshold, "dP_th (paper: 0.75)")->capture_default_str();
  app.add_option("--threshold-quantile", options.threshold_quantile,
                 "Use this quantile of dP over the trial as the threshold (0..1); negative: off")
      ->capture_default_str();
  app.add_option("--analysis-rate", options.analysis_rate, "Hz (paper Fig. 3: 100)")->capture_default_str();
  app.add_option("--min-duration", options.min_duration, "Shortest segment, s (reference implementation: 0.8)")
      ->capture_default_str();
  app.add_option("--momentum", options.momentum, "generalized (A u) | centroidal (about the centre of mass)")
      ->transform(CLI::CheckedTransformer(std::map<std::string, syn::MomentumKind>{
          {"generalized", syn::MomentumKind::kGeneralized}, {"centroidal", syn::MomentumKind::kCentroidal}}))
      ->default_str("generalized");
  const auto parameters = [&] {
    syn::RequireValid(options);
    return syn::WithFloatingBase(options.ToJson(), floating_base);
  };
  return syn::RunTool(app, argc, argv, parameters, [&] {
    syn::RequireValid(options);
    const syn::Model model = syn::LoadModel(model_path, floating_base);
    syn::PrintWarnings("syn-segment", model.warnings());
    syn::PrintNotes("syn-segment", model.notes(), common.verbose);
    const syn::MotionData motion = syn::ReadMotionFile(input);
    const syn::Segmentation segmentation = syn::SegmentMotion(motion, model, options);

    syn::Provenance provenance;
    provenance.schema = syn::kSegmentsSchema;
    provenance.schema_version = syn::kSegmentsSchemaVersion;
    provenance.producer = std::string("syn-segment ") + syn::kVersion;
    provenance.parameters = parameters();
    provenance.inputs = nlohmann::json::array({syn::DescribeInput(input), syn::DescribeInput(model_path)});
    syn::IntermediateWriter writer(common.output, provenance);
    syn::WriteSegmentsData(writer, segmentation);
    writer.commit();
    if (common.verbose) {
      for (size_t i = 0; i < segmentation.reasons.size(); ++i) {
        std::cerr << "  frame " << segmentation.boundaries[i] << ": " << segmentation.reasons[i] << "\n";
      }
    }
    std::cerr << "syn-segment: " << input << " -> " << common.output << ": " << segmentation.boundaries.size() - 1
              << " segments, threshold " << segmentation.threshold_used << "\n";
  });
}
