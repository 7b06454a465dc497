// How syn-export writes a number in text formats.
#pragma once

#include <string>

namespace syn {

// The shortest text that reads back to the same double (as nlohmann and the intermediate files print).
[[nodiscard]] std::string ShortestNumberText(double value);

}  // namespace syn
