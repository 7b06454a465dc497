#include "stages/export/number_text.h"

#include <cstdio>
#include <cstdlib>

namespace syn {

std::string ShortestNumberText(double value) {
  char text[32];
  for (int precision = 15; precision <= 17; ++precision) {
    std::snprintf(text, sizeof text, "%.*g", precision, value);
    if (std::strtod(text, nullptr) == value) break;
  }
  return text;
}

}  // namespace syn
