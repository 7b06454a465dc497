// TRC marker files (Motion Analysis / OpenSim): a path line, a key row and a
// value row (DataRate, NumFrames, NumMarkers, Units ...), marker names every
// third column, an X1 Y1 Z1 row, then one row per frame. Tab- or
// space-separated, CRLF or LF; blank fields and NaN in any spelling are
// missing samples. Lengths stay in the file's Units; OpenSim's TRC are Y up.
#pragma once

#include <string>
#include <string_view>

#include "common/marker_data.h"

namespace syn {

// Throws DataError at file:line. A NumFrames that disagrees with the rows
// present is a warning (the rows win).
[[nodiscard]] MarkerData ParseTrc(std::string_view text, const std::string& source_name);
[[nodiscard]] MarkerData ReadTrc(const std::string& path);

}  // namespace syn
