// The studio's parameters (syn-studio --help), with their defaults and why.
#pragma once

#include <cstddef>
#include <string>

#include <nlohmann/json.hpp>

#include "common/foot_sliding.h"

namespace syn {

struct StudioOptions {
  // Loopback by default: the studio reads and composes whatever a request names, so it is a local tool.
  std::string host = "127.0.0.1";
  int port = 8080;
  // A compose script is a few kB (manifests/scripts/dance_phrase.toml: 1.1 kB); 64 kB leaves room for
  // hundreds of keyframes and refuses (413) anything that is not a script.
  size_t max_body_bytes = 64 * 1024;
  // Bounds on one composition, so a request cannot run for long (compose costs about one integration per
  // step and per frame; a 4 s motion takes tens of milliseconds, tests/bench/studio_benchmark.cpp).
  double max_motion_seconds = 60.0;  // Σ repetitions × duration over the steps
  int max_pieces = 200;              // Σ repetitions
  int max_steps = 64;
  // Socket read and write timeouts: a client that stalls mid-request is dropped.
  int io_timeout_seconds = 5;
  // Metrics grid: syn-evaluate's default (the paper's 1 kHz control rate), so the page shows the numbers
  // syn-evaluate gives the saved script's motion. A 4 s motion's metrics cost ~9 ms of the 50 ms budget
  // (tests/bench/studio_benchmark.cpp); lower it for long motions on a slow machine.
  double eval_rate = 1000.0;  // Hz
  FootSlidingOptions sliding;  // syn-evaluate's defaults (common/foot_sliding.h)
  // Where the page (index.html, studio.js, studio.css) and three.js (npm, make report-npm) are read from.
  // Defaults: the source tree the binary was built from (tools/studio/web, tools/report/...).
  std::string web_root;
  std::string report_root;

  bool IsValid(std::string* error) const;
  nlohmann::json ToJson() const;
};

}  // namespace syn
