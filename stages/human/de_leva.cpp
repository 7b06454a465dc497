#include "stages/human/de_leva.h"

#include <string>

#include "common/error.h"

namespace syn {
namespace {

// de Leva (1996), Table 4. Columns: endpoints, length (mm), mass (%), CoM (% from the origin), radii of
// gyration (%) about the sagittal, transverse and longitudinal axes. Head, upper trunk and shank use the
// table's alternative definitions (lower half) whose endpoints are joint centres or C7.
const AnthropometricTable kFemale = {
    1735.0,
    61.9,
    {{
        {"VERT", "CERV", 243.7, 6.68, 48.41, 27.1, 29.5, 26.1},   // head (with neck)
        {"CERV", "XYPH", 228.0, 15.45, 50.50, 46.6, 31.4, 44.9},  // upper trunk
        {"XYPH", "OMPH", 205.3, 14.65, 45.12, 43.3, 35.4, 41.5},  // middle trunk
        {"OMPH", "MIDH", 181.5, 12.47, 49.20, 43.3, 40.2, 44.4},  // lower trunk
        {"SJC", "EJC", 275.1, 2.55, 57.54, 27.8, 26.0, 14.8},     // upper arm
        {"EJC", "WJC", 264.3, 1.38, 45.59, 26.1, 25.7, 9.4},      // forearm
        {"WJC", "MET3", 78.0, 0.56, 74.74, 53.1, 45.4, 33.5},     // hand
        {"HJC", "KJC", 368.5, 14.78, 36.12, 36.9, 36.4, 16.2},    // thigh
        {"KJC", "AJC", 438.6, 4.81, 43.52, 26.7, 26.3, 9.2},      // shank
        {"HEEL", "TTIP", 228.3, 1.29, 40.14, 29.9, 27.9, 13.9},   // foot
    }},
};

const AnthropometricTable kMale = {
    1741.0,
    73.0,
    {{
        {"VERT", "CERV", 242.9, 6.94, 50.02, 30.3, 31.5, 26.1},
        {"CERV", "XYPH", 242.1, 15.96, 50.66, 50.5, 32.0, 46.5},
        {"XYPH", "OMPH", 215.5, 16.33, 45.02, 48.2, 38.3, 46.8},
        {"OMPH", "MIDH", 145.7, 11.17, 61.15, 61.5, 55.1, 58.7},
        {"SJC", "EJC", 281.7, 2.71, 57.72, 28.5, 26.9, 15.8},
        {"EJC", "WJC", 268.9, 1.62, 45.74, 27.6, 26.5, 12.1},
        {"WJC", "MET3", 86.2, 0.61, 79.00, 62.8, 51.3, 40.1},
        {"HJC", "KJC", 422.2, 14.16, 40.95, 32.9, 32.9, 14.9},
        {"KJC", "AJC", 440.3, 4.33, 43.95, 25.1, 24.6, 10.2},
        {"HEEL", "TTIP", 258.1, 1.37, 44.15, 25.7, 24.5, 12.4},
    }},
};

}  // namespace

std::string_view SexName(Sex sex) { return sex == Sex::kFemale ? "f" : "m"; }

Sex SexFromName(std::string_view name) {
  if (name == "f" || name == "female") return Sex::kFemale;
  if (name == "m" || name == "male") return Sex::kMale;
  throw UsageError("sex must be f or m, not '" + std::string(name) + "'");
}

std::string_view SegmentName(Segment segment) {
  static constexpr std::string_view kNames[kSegmentCount] = {"head",    "upper_trunk", "middle_trunk", "lower_trunk",
                                                              "upper_arm", "forearm",   "hand",         "thigh",
                                                              "shank",   "foot"};
  return kNames[static_cast<size_t>(segment)];
}

double AnthropometricTable::wholeBodyMassPercent() const {
  double sum = 0;
  for (int s = 0; s < kSegmentCount; ++s) {
    const auto segment = static_cast<Segment>(s);
    const bool paired = segment != Segment::kHead && segment != Segment::kUpperTrunk &&
                        segment != Segment::kMiddleTrunk && segment != Segment::kLowerTrunk;
    sum += (paired ? 2.0 : 1.0) * (*this)[segment].mass_percent;
  }
  return sum;
}

const AnthropometricTable& DeLevaTable4(Sex sex) { return sex == Sex::kFemale ? kFemale : kMale; }

}  // namespace syn
