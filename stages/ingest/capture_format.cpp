#include "stages/ingest/capture_format.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <utility>

namespace syn {
namespace {

constexpr std::array<std::pair<CaptureFormat, std::string_view>, 5> kNames{{
    {CaptureFormat::kC3d, "c3d"},
    {CaptureFormat::kMotiveCsv, "motive-csv"},
    {CaptureFormat::kTrc, "trc"},
    {CaptureFormat::kBvh, "bvh"},
    {CaptureFormat::kNpy, "npy"},
}};

bool StartsWith(std::string_view text, std::string_view prefix) {
  return text.size() >= prefix.size() && text.compare(0, prefix.size(), prefix) == 0;
}

}  // namespace

std::string_view CaptureFormatName(CaptureFormat format) {
  for (const auto& [value, name] : kNames) {
    if (value == format) return name;
  }
  return "unknown";
}

std::optional<CaptureFormat> CaptureFormatFromName(std::string_view name) {
  for (const auto& [value, known] : kNames) {
    if (known == name) return value;
  }
  return std::nullopt;
}

std::optional<CaptureFormat> DetectCaptureFormat(std::string_view first_bytes) {
  std::string_view text = first_bytes;
  if (StartsWith(text, "\xEF\xBB\xBF")) text.remove_prefix(3);  // UTF-8 byte-order mark
  if (StartsWith(text, "\x93NUMPY")) return CaptureFormat::kNpy;
  if (StartsWith(text, "PathFileType")) return CaptureFormat::kTrc;
  if (StartsWith(text, "Format Version,")) return CaptureFormat::kMotiveCsv;
  if (StartsWith(text, "HIERARCHY")) return CaptureFormat::kBvh;
  // C3D: byte 0 points at the parameter block (>= 2), byte 1 is the key 0x50.
  if (first_bytes.size() >= 512 && static_cast<unsigned char>(first_bytes[1]) == 0x50 &&
      static_cast<unsigned char>(first_bytes[0]) >= 2) {
    return CaptureFormat::kC3d;
  }
  return std::nullopt;
}

std::optional<CaptureFormat> CaptureFormatFromExtension(const std::string& path) {
  const size_t dot = path.rfind('.');
  if (dot == std::string::npos) return std::nullopt;
  std::string extension = path.substr(dot + 1);
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension == "c3d") return CaptureFormat::kC3d;
  if (extension == "csv") return CaptureFormat::kMotiveCsv;
  if (extension == "trc") return CaptureFormat::kTrc;
  if (extension == "bvh") return CaptureFormat::kBvh;
  if (extension == "npy") return CaptureFormat::kNpy;
  return std::nullopt;
}

}  // namespace syn
