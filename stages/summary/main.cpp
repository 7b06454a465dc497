// syn-summary SYNERGIES... --table trials|segments|power-ratio -o TABLE.csv
#include <iostream>

#include "common/cli.h"
#include "stages/summary/summary_tables.h"

int main(int argc, char** argv) {
  CLI::App app{"Write an archive summary table as CSV: one row per trial (segments, durations, variance explained "
               "by the kept synergies) or one row per segment (frames, duration, PC1-PC3 variance ratios), or the "
               "human-vs-robot power ratio of each trial.",
               "syn-summary"};
  syn::CommonFlags common;
  syn::AddCommonFlags(app, common);
  std::vector<std::string> inputs, metrics, human_metrics;
  std::string table = "trials";
  std::string robot_name = "robot";
  app.add_option("INPUT", inputs, "Synergies files, in row order")->required();
  app.add_option("--metrics", metrics, "syn-evaluate JSON files, one per synergies file in the same order: adds "
                                        "dP, dKE, power, foot sliding and the rank-k changes to each row");
  app.add_option("--human-metrics", human_metrics,
                 "power-ratio table: syn-evaluate JSON of each trial retargeted onto the human model (same order); "
                 "--metrics then holds the robot's");
  app.add_option("--robot-name", robot_name, "power-ratio table: the robot column's value")->capture_default_str();
  app.add_option("--table", table, "trials | segments | power-ratio (one row per trial: human and robot mean power "
                                   "in W/kg, their ratio, the human's hip/knee/ankle share of leg power)")
      ->capture_default_str()
      ->check(CLI::IsMember({"trials", "segments", "power-ratio"}));
  return syn::RunTool(app, argc, argv, [&] {
    if (table == "power-ratio") {
      syn::WritePowerRatioTable(inputs, metrics, human_metrics, common.output, robot_name);
    } else {
      syn::WriteSummaryTable(inputs, metrics, table, common.output);
    }
    std::cerr << "syn-summary: " << inputs.size() << " trials -> " << common.output << "\n";
  });
}
