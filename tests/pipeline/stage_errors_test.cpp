// Every tool refuses what it must, with the documented exit code and a message that names the culprit:
// each enumerated flag and numeric range given a bad value (exit 2, the flag named), and for every stage a
// missing input, an output that cannot be written and an input of the wrong kind (exit 1, the file named,
// no output left). The commands are otherwise the valid ones of the stage chain (tests/pipeline/stage_chain.h),
// so the one wrong thing is what is refused.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "tests/pipeline/stage_chain.h"
#include "tests/support/run_command.h"
#include "tests/support/shared_data.h"

namespace syn::testing {
namespace {

namespace fs = std::filesystem;

struct BadValue {
  std::string command;  // a valid command but for `flag value`
  std::string flag;
  std::string value;
  std::string named_as;  // what the message may contain instead of the flag (empty: the flag only)
};

std::string Bin(const std::string& tool) { return BinPath(tool) + " "; }

std::vector<BadValue> BadValues(const StageChain& c) {
  const std::string out = " -o " + c.dir + "/bad-value.out";
  const std::string ingest = Bin("syn-ingest") + c.capture + out;
  const std::string retarget = Bin("syn-retarget") + c.markers + " --model " + c.model + " --robot-map " + c.robot_map +
                               " --markerset " + c.markerset + out;
  const std::string segment = Bin("syn-segment") + c.motion + " --model " + c.model + out;
  const std::string synergies = Bin("syn-synergies") + c.motion + " " + c.segments + out;
  const std::string evaluate = Bin("syn-evaluate") + c.motion + " --model " + c.model + out;
  const std::string export_mot = Bin("syn-export") + c.motion + " --model " + c.model + " -o " + c.dir + "/bad.mot";
  const std::string library = Bin("syn-library") + c.synergies + out;
  const std::string summary = Bin("syn-summary") + c.synergies + " --metrics " + c.metrics + out;
  const std::string project = Bin("syn-project") + c.motion + " --library " + c.library + " --model " + c.model +
                              " --robot-map " + c.robot_map + out;
  const std::string inspect = Bin("syn-inspect") + c.model;
  const std::string archive = Bin("syn-archive") + c.capture + " -o " + c.dir + "/bad-archive";
  return {
      {ingest, "--format", "xls", ""},
      {ingest, "--up-axis", "w", ""},
      {ingest, "--units", "furlongs", ""},
      {ingest, "--fill-gaps", "-1", ""},
      {ingest, "--fill-gaps", "some", ""},
      {ingest, "--rate", "-5", ""},
      {ingest, "--rate", "fast", ""},
      {ingest, "--bvh-scale", "-2", ""},
      {ingest, "--bvh-scale", "big", ""},
      {retarget, "--smoothing", "-1", ""},
      {retarget, "--velocity-limit-scale", "-1", ""},
      {retarget, "--posture-scale", "0", ""},
      {retarget, "--max-bridge", "-1", ""},
      {retarget, "--reference-time", "soon", ""},
      {segment, "--threshold", "0", ""},
      {segment, "--threshold-quantile", "1.5", ""},
      {segment, "--analysis-rate", "0", ""},
      {segment, "--min-duration", "-1", ""},
      {segment, "--momentum", "sideways", ""},
      {segment, "--floating-base", "sideways", "floating base"},
      {synergies, "--components", "0", ""},
      {synergies, "--velocities", "some", ""},
      {evaluate, "--eval-rate", "0", ""},
      {evaluate, "--samples", "-1", ""},
      {evaluate, "--alpha", "1", ""},
      {evaluate, "--alpha", "-0.1", ""},
      {evaluate, "--seed", "lucky", ""},
      {evaluate, "--contact-height", "-1", ""},
      {evaluate, "--slide-speed", "-1", ""},
      {evaluate, "--slide-window", "-1", ""},
      {evaluate, "--penetration", "-1", ""},
      {evaluate, "--floating-base", "sideways", "floating base"},
      {export_mot, "--format", "xls", ""},
      {export_mot, "--rate", "-1", ""},
      {export_mot, "--floating-base", "sideways", "floating base"},
      {library, "--components", "0", ""},
      {library, "--components", "few", ""},
      {summary, "--table", "chairs", ""},
      {project, "--floating-base", "sideways", "floating base"},
      {inspect, "--floating-base", "sideways", "floating base"},
      {archive, "--subjects", "0", ""},
      {archive, "--hours", "0", ""},
      {archive, "--rate", "0", ""},
      {archive, "--noise-mm", "-1", ""},
  };
}

TEST(StageErrors, EveryEnumeratedFlagAndNumericRangeRefusesABadValueAsUsage) {
  const StageChain& chain = Chain();
  for (const BadValue& bad : BadValues(chain)) {
    const std::string command = bad.command + " " + bad.flag + " " + bad.value;
    SCOPED_TRACE(command);
    const CommandResult result = RunCommand(command);
    EXPECT_EQ(result.exit_code, 2) << result.output;
    const bool named = result.output.find(bad.flag) != std::string::npos ||
                       (!bad.named_as.empty() && result.output.find(bad.named_as) != std::string::npos);
    EXPECT_TRUE(named) << "the message should name " << bad.flag << ":\n" << result.output;
    EXPECT_FALSE(fs::exists(chain.dir + "/bad-value.out"));
  }
}

struct StageCase {
  std::string stage;
  std::string missing_input;   // a command whose input does not exist
  std::string missing_path;
  std::string writes;          // a valid command but for its output, appended
  std::string wrong_kind;      // a command given a file of the wrong kind
  std::string wrong_path;
};

std::vector<StageCase> StageCases(const StageChain& c) {
  const std::string d = c.dir + "/";
  const std::string none = d + "does-not-exist";
  const std::string model = " --model " + c.model;
  const std::string tail = " -o " + d + "refused.out";
  // A tiny manifest for syn-plan.
  std::ofstream(d + "plan.toml") << "name = \"p\"\nroot = \"" << c.dir << "\"\n[[trial]]\nid = \"t\"\nfile = \"t.bvh\"\n";
  return {
      {"ingest", Bin("syn-ingest") + none + ".bvh" + tail, none + ".bvh", Bin("syn-ingest") + c.capture,
       Bin("syn-ingest") + c.motion + tail, c.motion},
      {"retarget",
       Bin("syn-retarget") + none + ".h5" + model + " --robot-map " + c.robot_map + " --markerset " + c.markerset + tail,
       none + ".h5", Bin("syn-retarget") + c.markers + model + " --robot-map " + c.robot_map + " --markerset " + c.markerset,
       Bin("syn-retarget") + c.motion + model + " --robot-map " + c.robot_map + " --markerset " + c.markerset + tail,
       c.motion},
      {"segment", Bin("syn-segment") + none + ".h5" + model + tail, none + ".h5", Bin("syn-segment") + c.motion + model,
       Bin("syn-segment") + c.markers + model + tail, c.markers},
      {"synergies", Bin("syn-synergies") + c.motion + " " + none + ".h5" + tail, none + ".h5",
       Bin("syn-synergies") + c.motion + " " + c.segments, Bin("syn-synergies") + c.motion + " " + c.motion + tail,
       c.motion},
      {"evaluate", Bin("syn-evaluate") + none + ".h5" + model + tail, none + ".h5",
       Bin("syn-evaluate") + c.motion + model + " --eval-rate 100",
       Bin("syn-evaluate") + c.motion + model + " --synergies " + c.segments + tail, c.segments},
      {"library", Bin("syn-library") + none + ".h5" + tail, none + ".h5", Bin("syn-library") + c.synergies,
       Bin("syn-library") + c.motion + tail, c.motion},
      {"summary", Bin("syn-summary") + c.synergies + " --metrics " + none + ".json" + tail, none + ".json",
       Bin("syn-summary") + c.synergies + " --metrics " + c.metrics,
       Bin("syn-summary") + c.synergies + " --metrics " + c.motion + tail, c.motion},
      {"export", Bin("syn-export") + none + ".h5 --format csv" + tail, none + ".h5",
       Bin("syn-export") + c.motion + " --format csv", Bin("syn-export") + c.markers + " --format csv" + tail, c.markers},
      {"project",
       Bin("syn-project") + none + ".h5 --library " + c.library + model + " --robot-map " + c.robot_map + tail,
       none + ".h5", Bin("syn-project") + c.motion + " --library " + c.library + model + " --robot-map " + c.robot_map,
       Bin("syn-project") + c.motion + " --library " + c.synergies + model + " --robot-map " + c.robot_map + tail,
       c.synergies},
      {"compose", Bin("syn-compose") + c.script + " --library " + none + ".h5" + tail, none + ".h5",
       Bin("syn-compose") + c.script + " --library " + c.library,
       Bin("syn-compose") + c.script + " --library " + c.motion + tail, c.motion},
      {"plan", Bin("syn-plan") + none + ".toml" + tail, none + ".toml", Bin("syn-plan") + d + "plan.toml",
       Bin("syn-plan") + c.markers + tail, c.markers},
      {"inspect", Bin("syn-inspect") + none + ".h5", none + ".h5", "", Bin("syn-inspect") + c.capture, c.capture},
  };
}

void ExpectRefusedNaming(const std::string& command, const std::string& path) {
  SCOPED_TRACE(command);
  const CommandResult result = RunCommand(command);
  EXPECT_EQ(result.exit_code, 1) << result.output;
  EXPECT_NE(result.output.find(path), std::string::npos) << "the message should name " << path << ":\n"
                                                         << result.output;
  EXPECT_EQ(result.output.find("internal error"), std::string::npos) << result.output;
}

TEST(StageErrors, EveryStageRefusesAMissingInputAnUnwritableOutputAndAWrongKindOfInput) {
  const StageChain& chain = Chain();
  // A path whose parent is a regular file: no stage can create it, whatever the user's rights.
  const std::string unwritable = chain.metrics + "/out";
  for (const StageCase& stage : StageCases(chain)) {
    SCOPED_TRACE(stage.stage);
    ExpectRefusedNaming(stage.missing_input, stage.missing_path);
    if (!stage.writes.empty()) ExpectRefusedNaming(stage.writes + " -o " + unwritable, unwritable);
    ExpectRefusedNaming(stage.wrong_kind, stage.wrong_path);
    EXPECT_FALSE(fs::exists(chain.dir + "/refused.out")) << "a refused run left its output";
  }
}

}  // namespace
}  // namespace syn::testing
