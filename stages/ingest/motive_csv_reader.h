// OptiTrack Motive CSV exports (format 1.21, 1.23 and later): a key/value
// first row (Format Version, Export Frame Rate, Rotation Type, Length Units
// ...), header rows Type / Name / ID / data kind / axis, then one row per
// frame. Markers, rigid-body markers and bone markers become labelled points;
// rigid bodies and bones become bodies (position + quaternion; Euler angles
// in degrees are composed in the order the Rotation Type names, R = R₁·R₂·R₃).
// Empty cells are missing samples. Lengths stay in Length Units; Y is up
// (Motive's default).
#pragma once

#include <string>
#include <string_view>

#include "common/marker_data.h"

namespace syn {

// Throws DataError at file:line; an export with no data columns is an error
// that says so.
[[nodiscard]] MarkerData ParseMotiveCsv(std::string_view text, const std::string& source_name);
[[nodiscard]] MarkerData ReadMotiveCsv(const std::string& path);

}  // namespace syn
