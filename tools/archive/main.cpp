// syn-archive BVH... -o OUT_DIR [--subjects 20 --hours 3 --seed 1]: a large synthetic archive for scale tests.
#include <filesystem>
#include <iostream>

#include "common/cli.h"
#include "common/file_bytes.h"
#include "tools/archive/archive_generator.h"

int main(int argc, char** argv) {
  CLI::App app{"Build a large capture archive from CMU BVH trials for scale tests: each trial one source's joint "
               "centres as the 22 HumanML3D joint markers (TRC, mm, Z up), time-warped (tempo 0.8-1.2 and a slow "
               "wobble), mirrored on half the trials, with Gaussian marker noise and interior gaps; plus "
               "OUT_DIR/archive.toml to run it. Seeded: same inputs, same bytes.",
               "syn-archive"};
  syn::CommonFlags common;
  syn::AddCommonFlags(app, common);
  std::vector<std::string> inputs;
  std::string index_path;
  syn::ArchiveOptions options;
  app.add_option("INPUT", inputs, "CMU BVH files (MotionBuilder- or 3dsMax-friendly conversions)")->required();
  app.add_option("--index", index_path, "cmu_bvh/index.csv: motion class and dance genre of each trial");
  app.add_option("--subjects", options.subjects, "Subjects")->capture_default_str();
  app.add_option("--hours", options.hours, "Hours of capture in all")->capture_default_str();
  app.add_option("--rate", options.rate, "Frame rate, Hz")->capture_default_str();
  app.add_option("--noise-mm", options.noise_mm, "Marker noise, standard deviation in mm")->capture_default_str();
  app.add_option("--gaps-per-second", options.gaps_per_second, "Gap starts per marker per second")->capture_default_str();
  app.add_option("--seed", options.seed, "Random seed")->capture_default_str();
  std::string protocol = "paper";
  app.add_option("--protocol", protocol,
                 "The manifest's metrics: paper (1 kHz, 100 Monte-Carlo reconstructions per segment) or throughput "
                 "(capture rate, no Monte-Carlo)")
      ->check(CLI::IsMember({"paper", "throughput"}))
      ->capture_default_str();
  return syn::RunTool(app, argc, argv, [&] {
    options.paper_protocol = protocol == "paper";
    if (options.subjects < 1 || !(options.hours > 0) || !(options.rate > 0) || options.noise_mm < 0) {
      throw syn::UsageError("--subjects, --hours and --rate must be positive, --noise-mm >= 0");
    }
    std::map<std::string, std::pair<std::string, std::string>> index;
    if (!index_path.empty()) index = syn::ReadCmuIndex(index_path);
    std::vector<syn::SourceTrial> sources;
    for (const std::string& input : inputs) {
      syn::SourceTrial source;
      source.path = input;
      source.id = std::filesystem::path(input).stem().string();
      const auto found = index.find(source.id);
      source.motion_class = found != index.end() ? found->second.first : "other";
      source.style = found != index.end() && !found->second.second.empty() ? found->second.second : source.motion_class;
      sources.push_back(source);
    }
    std::vector<std::string> skipped;
    const std::vector<syn::GeneratedTrial> trials = syn::GenerateArchive(sources, common.output, options, &skipped);
    syn::WriteFileAtomically(common.output + "/archive.toml",
                             syn::ArchiveManifest(trials, common.output + "/captures", options));
    int64_t frames = 0;
    for (const syn::GeneratedTrial& trial : trials) frames += trial.frames;
    std::cerr << "syn-archive: " << trials.size() << " trials, " << frames << " frames (" << frames / options.rate / 3600
              << " h) from " << sources.size() - skipped.size() << " sources -> " << common.output << "/archive.toml\n";
    for (const std::string& path : skipped) {
      std::cerr << "syn-archive: skipped " << path << " (not in the MotionBuilder-, 3dsMax- or Daz-friendly naming)\n";
    }
  });
}
