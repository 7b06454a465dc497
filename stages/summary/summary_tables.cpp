#include "stages/summary/summary_tables.h"

#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

#include "common/error.h"
#include "common/file_bytes.h"
#include "stages/synergies/synergies.h"

namespace syn {
namespace {

std::string Number(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.6g", value);
  return text;
}

// CSV cell: quoted when it holds a comma or a quote.
std::string Cell(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string quoted(1, '"');
  for (char c : text) {
    quoted.push_back(c);
    if (c == '"') quoted.push_back('"');
  }
  quoted.push_back('"');
  return quoted;
}

}  // namespace

void WriteSummaryTable(const std::vector<std::string>& synergies_files, const std::string& table, const std::string& output) {
  // (Rows are built with a stream: GCC 12 warns falsely on chains of std::string operator+.)
  std::ostringstream text;
  if (table == "trials") {
    text << "trial,subject,style,motion_class,segments,duration_s,mean_segment_duration_s,"
            "variance_explained_by_kept_synergies,median_components_for_90_percent\n";
  } else if (table == "segments") {
    text << "trial,style,motion_class,segment,start_frame,end_frame,duration_s,pc1_ratio,pc2_ratio,pc3_ratio,"
            "variance_explained_by_kept_synergies,components_for_90_percent\n";
  } else {
    throw UsageError("--table must be trials or segments");
  }
  for (const std::string& file : synergies_files) {
    SynergyOptions labels;
    const TrialSynergies trial = ReadTrialSynergies(file, &labels);
    double duration = 0, explained = 0;
    std::vector<int> k90;
    for (size_t s = 0; s < trial.segments.size(); ++s) {
      const auto& segment = trial.segments[s];
      const auto& ratio = segment.synergies.explained_variance_ratio;
      duration += segment.duration;
      explained += ratio.sum();
      k90.push_back(segment.synergies.components_for_90_percent);
      if (table == "segments") {
        text << Cell(labels.trial) << ',' << Cell(labels.style) << ',' << Cell(labels.motion_class) << ',' << s << ','
             << segment.start_frame << ',' << segment.end_frame << ',' << Number(segment.duration);
        for (int k = 0; k < 3; ++k) text << ',' << (k < ratio.size() ? Number(ratio[k]) : std::string());
        text << ',' << Number(ratio.sum()) << ',' << segment.synergies.components_for_90_percent << '\n';
      }
    }
    if (table == "trials") {
      const double count = static_cast<double>(trial.segments.size());
      std::sort(k90.begin(), k90.end());
      text << Cell(labels.trial) << ',' << Cell(labels.subject) << ',' << Cell(labels.style) << ','
           << Cell(labels.motion_class) << ',' << trial.segments.size() << ',' << Number(duration) << ','
           << Number(count > 0 ? duration / count : 0) << ',' << Number(count > 0 ? explained / count : 0) << ','
           << (k90.empty() ? std::string() : std::to_string(k90[k90.size() / 2])) << '\n';
    }
  }
  WriteFileAtomically(output, text.str());
}

}  // namespace syn
