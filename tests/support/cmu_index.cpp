#include "tests/support/cmu_index.h"

#include <algorithm>
#include <fstream>

#include "stages/ingest/text_fields.h"
#include "tests/support/shared_data.h"

namespace syn::testing {

std::vector<CmuTrial> CmuTrials(const std::vector<std::string>& classes) {
  std::ifstream in(SharedPath("cmu_bvh/index.csv"));
  std::string line;
  std::getline(in, line);  // the header
  std::vector<CmuTrial> trials;
  while (std::getline(in, line)) {
    const std::vector<std::string> cells = SplitQuotedCsv(line);
    if (cells.size() >= 5 && std::find(classes.begin(), classes.end(), cells[4]) != classes.end()) {
      trials.push_back({cells[1], cells[2], cells[4]});
    }
  }
  return trials;
}

}  // namespace syn::testing
