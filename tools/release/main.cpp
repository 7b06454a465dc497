// syn-release build MANIFEST [-o TAR] | syn-release verify RELEASE.tar|DIR [--rebuild]: the dataset release of
// a manifest (tools/release/release_contents.h lists what it holds; release_verify.h what verify checks).
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iomanip>
#include <iostream>

#include "common/cli.h"
#include "common/release_manifest.h"
#include "common/sha256.h"
#include "tools/release/release_build.h"
#include "tools/release/release_verify.h"

namespace {

std::string Megabytes(uint64_t bytes) {
  char text[32];
  std::snprintf(text, sizeof text, "%10.2f MB", static_cast<double>(bytes) / 1e6);
  return text;
}

std::string OwnFolder() {
  std::error_code error;
  const std::filesystem::path self = std::filesystem::read_symlink("/proc/self/exe", error);
  return error ? std::string(".") : self.parent_path().string();
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"Dataset releases: `build` writes the deterministic tar of a manifest's pipeline outputs (robot motions, "
               "exports, quality table, datasheet README.md, libraries, checksums) and prints its size per part; "
               "`verify` checks a release tar or folder (checksums, schemas, every trial present, the datasheet) and "
               "with --rebuild re-runs the pipeline from the captures and compares every byte. Exit 0 when it passes, "
               "1 with the first difference (file and what differs).",
               "syn-release"};
  app.set_version_flag("--version", std::string("syn-release ") + syn::kVersion);
  app.require_subcommand(1);

  CLI::App* build = app.add_subcommand("build", "Write NAME-VERSION.tar from outputs/NAME (after `make run`)");
  std::string manifest_path, outputs_root = "outputs", tar_path, dataset_root;
  build->add_option("MANIFEST", manifest_path, "Dataset manifest (TOML)")->required();
  build->add_option("--outputs", outputs_root, "Folder holding outputs/<name>/")->capture_default_str();
  build->add_option("-o,--output", tar_path, "The tar (default: OUTPUTS/NAME/release/NAME-VERSION.tar)");
  build->add_option("--dataset-root", dataset_root,
                    "The captures' folder as syn-plan was given it (default: $DATASET_ROOT, else the manifest's root); "
                    "recorded for verify --rebuild");

  CLI::App* verify = app.add_subcommand("verify", "Check a release tar or extracted folder");
  std::string release;
  syn::VerifyOptions options;
  options.bin_dir = OwnFolder();
  verify->add_option("RELEASE", release, "NAME-VERSION.tar or an extracted NAME-VERSION folder")->required();
  verify->add_flag("--rebuild", options.rebuild,
                   "Re-run the pipeline from the captures (syn-plan + make in a scratch tree beside --source-dir) and "
                   "compare every file byte for byte");
  verify->add_option("--source-dir", options.source_dir, "The synsculpt tree the manifest's paths are relative to")
      ->capture_default_str();
  verify->add_option("--bin", options.bin_dir, "Folder of the syn-* tools (default: syn-release's own)");
  verify->add_option("--dataset-root", options.dataset_root, "The captures' folder (default: the one provenance.json records)");
  verify->add_option("-j,--jobs", options.jobs, "Parallel jobs of the rebuild")->capture_default_str();
  verify->add_flag("--keep-scratch", options.keep_scratch, "Keep the rebuild's scratch tree");

  return syn::RunTool(app, argc, argv, [&] {
    if (*build) {
      const syn::ReleaseManifest manifest = syn::ReadReleaseManifest(manifest_path);
      if (dataset_root.empty()) dataset_root = std::getenv("DATASET_ROOT") ? std::getenv("DATASET_ROOT") : manifest.root;
      for (const std::string& warning : manifest.licenceWarnings()) std::cerr << "syn-release: warning: " << warning << "\n";
      if (tar_path.empty()) {
        tar_path = outputs_root + "/" + manifest.name + "/release/" + syn::ReleaseFolderName(manifest) + ".tar";
      }
      std::filesystem::create_directories(std::filesystem::path(tar_path).parent_path().empty()
                                              ? std::filesystem::path(".")
                                              : std::filesystem::path(tar_path).parent_path());
      const syn::ReleaseSizes sizes = syn::BuildRelease(manifest, outputs_root, dataset_root, tar_path);
      uint64_t contents = 0;
      std::cerr << "syn-release: " << tar_path << " (" << manifest.trials.size() << " trials)\n";
      for (const auto& [part, bytes] : sizes.parts) {
        std::cerr << "  " << std::left << std::setw(32) << part << Megabytes(bytes) << "\n";
        contents += bytes;
      }
      std::cerr << "  " << std::left << std::setw(32) << "tar headers and padding" << Megabytes(sizes.tar_bytes - contents) << "\n"
                << "  " << std::left << std::setw(32) << "total" << Megabytes(sizes.tar_bytes) << "\n";
      std::cout << "release " << tar_path << " sha256 " << syn::Sha256OfFile(tar_path) << "\n";
      return;
    }
    const syn::VerifySummary summary = syn::VerifyRelease(release, options);
    for (const std::string& note : summary.notes) std::cerr << "syn-release: note: " << note << "\n";
    std::cout << "syn-release: " << release << ": verified " << summary.release_folder << ": " << summary.files
              << " files, " << summary.trials << " trials: checksums, schemas, trials present, datasheet"
              << (summary.rebuilt ? ", rebuilt from the captures byte for byte" : "") << "\n";
  });
}
