// Segment inertia parameters of adult humans: de Leva P. (1996) Adjustments to Zatsiorsky-Seluyanov's
// segment inertia parameters. J. Biomech. 29(9):1223-1230, Table 4, for females and males.
//
// Each segment runs from its origin to its other endpoint (de Leva's landmarks, named below); the
// centre of mass lies on that line at `com_percent` of the length from the origin; the radii of
// gyration are percentages of the length about the segment's sagittal (antero-posterior), transverse
// (medio-lateral) and longitudinal axes. Lengths are those of de Leva's reference subjects (statures
// 1735 mm female, 1741 mm male): a subject of another stature scales them by stature ratio.
//
// Where Table 4 gives two definitions of a segment, the one whose endpoints are the joints of the
// model is used: the head from the vertex to C7 (CERV), the upper trunk from C7 to the xiphoid, the
// shank from the knee to the ankle joint centre (the table's lower half).
#pragma once

#include <array>
#include <string_view>

namespace syn {

enum class Sex { kFemale, kMale };

[[nodiscard]] std::string_view SexName(Sex sex);  // "f", "m"
// "f" / "female" / "m" / "male"; throws UsageError for anything else.
[[nodiscard]] Sex SexFromName(std::string_view name);

enum class Segment { kHead, kUpperTrunk, kMiddleTrunk, kLowerTrunk, kUpperArm, kForearm, kHand, kThigh, kShank, kFoot };
inline constexpr int kSegmentCount = 10;
[[nodiscard]] std::string_view SegmentName(Segment segment);

struct SegmentParameters {
  std::string_view origin, other_end;  // de Leva's endpoint landmarks (VERT, CERV, XYPH, OMPH, MIDH, SJC ...)
  double length_mm = 0;                // reference subject
  double mass_percent = 0;             // of body mass
  double com_percent = 0;              // of the length, from the origin
  double radius_sagittal_percent = 0;  // of the length
  double radius_transverse_percent = 0;
  double radius_longitudinal_percent = 0;
};

struct AnthropometricTable {
  double stature_mm = 0;    // reference subject
  double body_mass_kg = 0;  // reference subject
  std::array<SegmentParameters, kSegmentCount> segments;

  const SegmentParameters& operator[](Segment segment) const { return segments[static_cast<size_t>(segment)]; }
  // Sum of the mass percentages over the whole body (paired segments twice): 100.00 for males,
  // 99.99 for females (the table's rounding).
  [[nodiscard]] double wholeBodyMassPercent() const;
};

[[nodiscard]] const AnthropometricTable& DeLevaTable4(Sex sex);

}  // namespace syn
