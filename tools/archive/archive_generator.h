// A large synthetic capture archive from real CMU trials, for testing the
// pipeline at scale (`make bench-archive`): each generated trial is one CMU
// BVH trial's joint centres, written as the 22 HumanML3D joint markers in a
// TRC file, after
//   - a time warp t_src(τ) = r τ + A sin(2π τ / P): tempo r ∈ [0.8, 1.2] and a
//     slow (P = 4 s) monotone speed wobble,
//   - a mirror (left ↔ right, y → −y) on half of the trials,
//   - Gaussian marker noise (default σ = 1 mm),
//   - gaps: each marker drops out at 0.2 per second for 3–30 frames (blank TRC
//     fields; syn-ingest --fill-gaps 30 bridges them).
// Subjects draw trials round-robin from a per-subject shuffle until they hold
// hours × 3600 / subjects seconds. Seeded: same inputs, same bytes.
#pragma once

#include <cstdint>
#include <map>
#include <string>
#include <vector>

namespace syn {

struct ArchiveOptions {
  int subjects = 20;
  double hours = 3.0;        // in all
  double rate = 120.0;       // Hz
  double noise_mm = 1.0;
  double gaps_per_second = 0.2;
  uint64_t seed = 1;
  // The manifest's [evaluate]: true for the paper's protocol (syn-evaluate's defaults: 1 kHz, 100
  // Monte-Carlo reconstructions per segment; about 0.18 CPU-s per second of G1 motion since issue 19, so
  // 3 h cost about 33 CPU-minutes), false for throughput only (metrics at the capture rate, no Monte-Carlo).
  bool paper_protocol = true;
};

struct SourceTrial {
  std::string path;               // a CMU BVH file
  std::string id;                 // e.g. 05_02
  std::string motion_class, style;
};

struct GeneratedTrial {
  std::string id, subject, file, motion_class, style, source;
  double duration_s = 0;
  int64_t frames = 0;
  bool mirrored = false;
};

// Reads every source once, writes `output_dir`/captures/*.trc and returns what it wrote. Sources in none
// of the three cgspeed naming conventions are skipped, and listed in `skipped`.
[[nodiscard]] std::vector<GeneratedTrial> GenerateArchive(const std::vector<SourceTrial>& sources,
                                                          const std::string& output_dir, const ArchiveOptions& options,
                                                          std::vector<std::string>* skipped);

// The manifest that runs the generated archive (G1, humanml3d22 marker set, gap filling on).
[[nodiscard]] std::string ArchiveManifest(const std::vector<GeneratedTrial>& trials, const std::string& captures_root,
                                          const ArchiveOptions& options);

// index.csv of ../shared/datasets/cmu_bvh: trial -> (motion class, dance genre).
[[nodiscard]] std::map<std::string, std::pair<std::string, std::string>> ReadCmuIndex(const std::string& path);

}  // namespace syn
