// Which reader a capture file needs, decided from its first bytes; the file
// name's extension only confirms (a mismatch is a warning, not a decision).
#pragma once

#include <optional>
#include <string>
#include <string_view>

namespace syn {

enum class CaptureFormat { kC3d, kMotiveCsv, kTrc, kBvh, kNpy };

[[nodiscard]] std::string_view CaptureFormatName(CaptureFormat format);  // "c3d", "motive-csv", ...
[[nodiscard]] std::optional<CaptureFormat> CaptureFormatFromName(std::string_view name);

// Looks at the first bytes of a file: C3D has the key byte 0x50 at offset 1;
// TRC starts with "PathFileType", Motive CSV with "Format Version,", BVH with
// "HIERARCHY", NPY with "\x93NUMPY". Returns nullopt when none matches.
[[nodiscard]] std::optional<CaptureFormat> DetectCaptureFormat(std::string_view first_bytes);

// The format a file extension suggests (".c3d", ".csv", ".trc", ".bvh", ".npy"), if any.
[[nodiscard]] std::optional<CaptureFormat> CaptureFormatFromExtension(const std::string& path);

}  // namespace syn
