// Every stage's CLI once on one short bundled capture (datasets/demo/14_14_excerpt.bvh onto the G1), as
// syn-plan's rules run them, into a folder that lives as long as the test process. The stage tests in this
// group read what the tools wrote and feed it back to them with one thing wrong.
#pragma once

#include <gtest/gtest.h>
#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <string>

#include "common/motion_file.h"
#include "tests/support/demo_motion.h"
#include "tests/support/run_command.h"
#include "tests/support/shared_data.h"

namespace syn::testing {

struct StageChain {
  std::string dir;
  std::string model, robot_map, markerset;   // inputs from the repository
  std::string capture;                       // a copy of the BVH
  std::string markers, motion, segments, synergies, metrics, evaluate_csv, library, summary_trials,
      summary_segments, mot_at_double_rate, script, composed;
  double rate_hz = 0;  // the motion's frame rate
};

// Runs `command`; a failing stage stops the process with its output (every test here needs the chain).
inline void RunStage(const std::string& command) {
  const CommandResult result = RunCommand(command);
  if (result.exit_code != 0) {
    std::fprintf(stderr, "stage chain: `%s` exited %d:\n%s\n", command.c_str(), result.exit_code, result.output.c_str());
    std::abort();
  }
}

inline const StageChain& Chain() {
  static const StageChain chain = [] {
    StageChain c;
    c.dir = (std::filesystem::temp_directory_path() / ("syn_chain_" + std::to_string(::getpid()))).string();
    std::filesystem::remove_all(c.dir);
    std::filesystem::create_directories(c.dir);
    std::atexit([] { std::filesystem::remove_all(std::filesystem::temp_directory_path() /
                                                 ("syn_chain_" + std::to_string(::getpid()))); });
    c.model = SourcePath(kG1Urdf);
    c.robot_map = SourcePath(kG1Map);
    c.markerset = SourcePath("manifests/markersets/cmu-bvh.toml");
    c.capture = c.dir + "/t.bvh";
    std::filesystem::copy_file(SourcePath("datasets/demo/14_14_excerpt.bvh"), c.capture);
    const std::string d = c.dir + "/";
    c.markers = d + "t.markers.h5";
    c.motion = d + "t.motion.h5";
    c.segments = d + "t.segments.h5";
    c.synergies = d + "t.synergies.h5";
    c.metrics = d + "t.metrics.json";
    c.evaluate_csv = d + "t.segments.csv";
    c.library = d + "library.h5";
    c.summary_trials = d + "trials.csv";
    c.summary_segments = d + "segments.csv";
    c.mot_at_double_rate = d + "t.mot";
    c.script = d + "script.toml";
    c.composed = d + "composed.motion.h5";
    const std::string bin = std::string(SYN_BIN_DIR) + "/";
    RunStage(bin + "syn-ingest " + c.capture + " -o " + c.markers);
    RunStage(bin + "syn-retarget " + c.markers + " --model " + c.model + " --robot-map " + c.robot_map +
             " --markerset " + c.markerset + " -o " + c.motion);
    const MotionData motion = ReadMotionFile(c.motion);
    c.rate_hz = 1.0 / (motion.time_s[1] - motion.time_s[0]);
    char rate[64], double_rate[64];
    std::snprintf(rate, sizeof rate, "%.17g", c.rate_hz);
    std::snprintf(double_rate, sizeof double_rate, "%.17g", 2 * c.rate_hz);
    RunStage(bin + "syn-segment " + c.motion + " --model " + c.model + " -o " + c.segments);
    RunStage(bin + "syn-synergies " + c.motion + " " + c.segments + " --trial t --style jacks --subject 14 -o " +
             c.synergies);
    // The evaluation grid on the motion's own samples (--eval-rate = its frame rate), so the tests can sum.
    RunStage(bin + "syn-evaluate " + c.motion + " --model " + c.model + " --robot-map " + c.robot_map +
             " --synergies " + c.synergies + " --samples 5 --eval-rate " + rate + " --csv " + c.evaluate_csv +
             " -o " + c.metrics);
    RunStage(bin + "syn-library " + c.synergies + " -o " + c.library);
    RunStage(bin + "syn-summary " + c.synergies + " --metrics " + c.metrics + " --table trials -o " + c.summary_trials);
    RunStage(bin + "syn-summary " + c.synergies + " --metrics " + c.metrics + " --table segments -o " +
             c.summary_segments);
    RunStage(bin + "syn-export " + c.motion + " --format mot --model " + c.model + " --rate " + double_rate + " -o " +
             c.mot_at_double_rate);
    FILE* script = std::fopen(c.script.c_str(), "w");
    std::fprintf(script, "model = \"%s\"\n\n[[step]]\nsynergy = \"jacks/t/0\"\n", c.model.c_str());
    std::fclose(script);
    RunStage(bin + "syn-compose " + c.script + " --library " + c.library + " -o " + c.composed);
    return c;
  }();
  return chain;
}

}  // namespace syn::testing
