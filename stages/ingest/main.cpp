// syn-ingest INPUT -o OUT.markers.h5: read a capture file (C3D, Motive CSV,
// TRC, BVH, HumanML3D joints .npy) into SI units, Z up, missing samples NaN.
#include <iostream>

#include "common/cli.h"
#include "common/intermediate_file.h"
#include "common/markers_file.h"
#include "stages/ingest/ingest.h"

int main(int argc, char** argv) {
  CLI::App app{"Read a motion-capture file (C3D, Motive CSV, TRC, BVH, HumanML3D joints .npy) into a markers "
               "file: SI units, Z up, missing samples NaN. The format is detected from the file's content.",
               "syn-ingest"};
  syn::CommonFlags common;
  syn::AddCommonFlags(app, common);
  syn::IngestOptions options;
  std::string input;
  app.add_option("INPUT", input, "Capture file")->required();
  app.add_option("--format", options.format, "auto | c3d | motive-csv | trc | bvh | npy")->capture_default_str();
  app.add_option("--up-axis", options.up_axis,
                 "auto | x | y | z: the file's vertical axis. auto: decided from the data (the axis of the body's "
                 "largest extent, and the axis along which the lowest point stays at floor height while the subject "
                 "travels); when the data cannot tell (or the two cues disagree, e.g. lying on the floor), the "
                 "format's convention: C3D POINT:Y_SCREEN (else Z); TRC, Motive CSV, BVH and HumanML3D Y. The summary "
                 "line says which axis and why; a data choice against the convention is a warning")
      ->capture_default_str();
  app.add_option("--units", options.units, "auto | mm | cm | m: the file's length unit (auto: as the file says)")
      ->capture_default_str();
  app.add_option("--fill-gaps", options.fill_gaps,
                 "Fill interior marker gaps of at most this many frames with a cubic spline (0: none)")
      ->capture_default_str();
  app.add_option("--rate", options.rate, "Override the frame rate stated in the file, in Hz (0: keep it)")
      ->capture_default_str();
  app.add_flag("--strip-prefix", options.strip_prefix, "Remove subject prefixes such as 'Male:' from labels");
  app.add_option("--bvh-scale", options.bvh_scale,
                 "Metres per BVH unit, or auto: from the rest-pose height (10-50 units: CMU's ASF unit 0.056444 m; "
                 "50-100: inches; 100-250: centimetres; 1-2.5: metres)")
      ->capture_default_str();
  app.add_flag("--drop-first-frame", options.drop_first_frame,
               "Drop BVH frame 0 (the T-pose frame CMU BVH converters add)");
  return syn::RunTool(app, argc, argv, [&] {
        syn::RequireValid(options);
        return options.ToJson();
      }, [&] {
    syn::RequireValid(options);
    if (common.verbose) std::cerr << "syn-ingest parameters: " << syn::CanonicalJson(options.ToJson()) << "\n";

    syn::IngestSummary summary;
    const syn::MarkerData data = syn::IngestCapture(input, options, &summary);
    for (const std::string& warning : data.warnings) std::cerr << "syn-ingest: warning: " << input << ": " << syn::Printable(warning) << "\n";

    syn::Provenance provenance;
    provenance.schema = syn::kMarkersSchema;
    provenance.schema_version = syn::kMarkersSchemaVersion;
    provenance.producer = std::string("syn-ingest ") + syn::kVersion;
    provenance.parameters = options.ToJson();
    provenance.inputs = nlohmann::json::array({syn::DescribeInput(input)});
    syn::IntermediateWriter writer(common.output, provenance);
    syn::WriteMarkerData(writer, data);
    writer.commit();

    if (common.verbose) {
      for (size_t m = 0; m < summary.gaps.size(); ++m) {
        const syn::MarkerGapReport& gap = summary.gaps[m];
        std::cerr << "  " << data.labels[m] << ": " << gap.gaps << " gaps, " << gap.gaps_filled << " filled, "
                  << gap.missing_after << " of " << data.frame_count() << " samples missing\n";
      }
    }
    std::cerr << "syn-ingest: " << input << " -> " << common.output << ": " << summary.BriefReport() << "\n";
  });
}
