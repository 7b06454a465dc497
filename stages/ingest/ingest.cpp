#include "stages/ingest/ingest.h"

#include <cctype>
#include <charconv>
#include <cmath>
#include <sstream>

#include "common/error.h"
#include "common/file_bytes.h"
#include "stages/ingest/capture_format.h"
#include "stages/ingest/capture_normalization.h"
#include "stages/ingest/bvh_reader.h"
#include "stages/ingest/c3d_reader.h"
#include "stages/ingest/motive_csv_reader.h"
#include "stages/ingest/npy_reader.h"
#include "stages/ingest/trc_reader.h"

namespace syn {
namespace {

bool ParsePositiveNumber(const std::string& text, double* value) {
  const char* end = text.data() + text.size();
  auto [ptr, ec] = std::from_chars(text.data(), end, *value);
  return ec == std::errc() && ptr == end && std::isfinite(*value) && *value > 0;
}

double UnitToMetres(const std::string& units) {
  if (units == "mm") return 0.001;
  if (units == "cm") return 0.01;
  if (units == "m") return 1.0;
  return 0.0;  // auto
}

CaptureFormat ResolveFormat(const std::string& path, const std::string& requested, const std::vector<uint8_t>& bytes,
                            std::vector<std::string>& warnings) {
  const std::string_view head(reinterpret_cast<const char*>(bytes.data()), std::min<size_t>(bytes.size(), 512));
  const std::optional<CaptureFormat> detected = DetectCaptureFormat(head);
  const std::optional<CaptureFormat> by_extension = CaptureFormatFromExtension(path);
  if (requested != "auto") return *CaptureFormatFromName(requested);
  if (detected) {
    if (by_extension && *by_extension != *detected) {
      warnings.push_back("content looks like " + std::string(CaptureFormatName(*detected)) +
                         " although the extension suggests " + std::string(CaptureFormatName(*by_extension)));
    }
    return *detected;
  }
  // A C3D whose parameter header lacks the 0x50 key (c3d.org sample08
  // TESTAPI) still has a plausible block pointer; trust the extension then.
  if (by_extension == CaptureFormat::kC3d) return CaptureFormat::kC3d;
  throw DataError(Location::AtByte(path, 0),
                  "unrecognised format: expected a C3D file (key byte 0x50 at offset 1), a TRC ('PathFileType'), a "
                  "Motive CSV ('Format Version,'), a BVH ('HIERARCHY') or an NPY array; use --format to force one");
}

MarkerData ReadWithFormat(const std::string& path, CaptureFormat format, const std::vector<uint8_t>& bytes,
                          const IngestOptions& options) {
  const std::string_view text(reinterpret_cast<const char*>(bytes.data()), bytes.size());
  switch (format) {
    case CaptureFormat::kC3d:
      return ParseC3d(bytes.data(), bytes.size(), path);
    case CaptureFormat::kTrc:
      return ParseTrc(text, path);
    case CaptureFormat::kMotiveCsv:
      return ParseMotiveCsv(text, path);
    case CaptureFormat::kNpy:
      return HumanMl3dJointsToMarkerData(ParseNpy(bytes.data(), bytes.size(), path), path);
    case CaptureFormat::kBvh: {
      BvhOptions bvh;
      bvh.drop_first_frame = options.drop_first_frame;
      MarkerData data = ParseBvh(text, path, bvh);
      double scale = 0.0;
      if (!ParsePositiveNumber(options.bvh_scale, &scale)) scale = GuessBvhScaleToMetres(data);
      data.length_unit_to_m = scale;
      return data;
    }
  }
  throw DataError(Location::InFile(path), "unsupported format");
}

}  // namespace

bool IngestOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& message) {
    if (error) *error = message;
    return false;
  };
  if (format != "auto" && !CaptureFormatFromName(format)) {
    return fail("--format must be auto, c3d, motive-csv, trc, bvh or npy, not '" + format + "'");
  }
  if (up_axis != "auto" && up_axis != "x" && up_axis != "y" && up_axis != "z") {
    return fail("--up-axis must be auto, x, y or z, not '" + up_axis + "'");
  }
  if (units != "auto" && UnitToMetres(units) == 0.0) return fail("--units must be auto, mm, cm or m, not '" + units + "'");
  if (fill_gaps < 0) return fail("--fill-gaps must be >= 0 frames");
  if (rate < 0 || !std::isfinite(rate)) return fail("--rate must be a positive frame rate in Hz (0 keeps the file's)");
  double scale = 0;
  if (bvh_scale != "auto" && !ParsePositiveNumber(bvh_scale, &scale)) {
    return fail("--bvh-scale must be auto or a positive number of metres per BVH unit, not '" + bvh_scale + "'");
  }
  return true;
}

nlohmann::json IngestOptions::ToJson() const {
  return {{"format", format},       {"up_axis", up_axis},       {"units", units},
          {"fill_gaps", fill_gaps}, {"rate", rate},             {"strip_prefix", strip_prefix},
          {"bvh_scale", bvh_scale}, {"drop_first_frame", drop_first_frame}};
}

std::string IngestSummary::BriefReport() const {
  int64_t filled = 0, missing = 0;
  for (const MarkerGapReport& gap : gaps) {
    filled += gap.gaps_filled;
    missing += gap.missing_after;
  }
  std::ostringstream out;
  out << format << ": " << frames << " frames at " << rate_hz << " Hz, " << markers << " markers, " << bodies
      << " bodies, " << analog_channels << " analog channels; " << filled << " gaps filled, " << missing
      << " marker samples missing; up axis " << static_cast<char>(std::toupper(up_axis)) << " (" << up_axis_reason << ")";
  if (dropped_lead_frames == 1) out << "; frame 0 dropped (the calibration frame, kept aside)";
  if (dropped_lead_frames > 1) {
    const int64_t zero_frames = dropped_lead_frames - 1 - dropped_ease_in_frames - dropped_teleport_frames - dropped_held_frames;
    out << "; the first " << dropped_lead_frames << " frames dropped (the calibration frame, kept aside";
    if (zero_frames > 0) {
      out << "; " << zero_frames << " reference frame" << (zero_frames > 1 ? "s" : "") << " left at zero, whole or a joint";
    }
    if (dropped_held_frames > 0) out << "; " << dropped_held_frames << " holding one pose before the take moves";
    if (dropped_ease_in_frames > 0) out << "; " << dropped_ease_in_frames << " easing in from it";
    if (dropped_teleport_frames > 0) {
      out << "; " << dropped_teleport_frames << " before a joint jumped faster than any body moves";
    }
    out << ")";
  }
  return out.str();
}

MarkerData IngestCapture(const std::string& path, const IngestOptions& options, IngestSummary* summary) {
  const std::vector<uint8_t> bytes = ReadFileBytes(path);
  std::vector<std::string> warnings;
  const CaptureFormat format = ResolveFormat(path, options.format, bytes, warnings);
  MarkerData data = ReadWithFormat(path, format, bytes, options);
  data.warnings.insert(data.warnings.begin(), warnings.begin(), warnings.end());
  if (data.frame_count() == 0) data.warnings.push_back("the file holds no frames");

  NormalizationOptions normalization;
  normalization.up_axis = options.up_axis == "auto" ? 'a' : options.up_axis[0];
  normalization.length_unit_to_m = UnitToMetres(options.units);
  normalization.rate_hz = options.rate;
  normalization.strip_prefix = options.strip_prefix;
  NormalizeCapture(data, normalization);

  std::vector<MarkerGapReport> gaps = FillMarkerGaps(data, options.fill_gaps);
  data.metadata["source_format"] = std::string(CaptureFormatName(format));
  nlohmann::json gap_report = nlohmann::json::object();
  for (size_t m = 0; m < gaps.size(); ++m) {
    gap_report[data.labels[m]] = {{"gaps", gaps[m].gaps},
                                  {"gaps_filled", gaps[m].gaps_filled},
                                  {"missing_before", gaps[m].missing_before},
                                  {"missing_after", gaps[m].missing_after}};
  }
  data.metadata["gap_report"] = gap_report;
  if (summary) {
    summary->format = std::string(CaptureFormatName(format));
    summary->frames = data.frame_count();
    summary->markers = data.marker_count();
    summary->bodies = static_cast<int64_t>(data.bodies.size());
    summary->analog_channels = static_cast<int64_t>(data.analog_labels.size());
    summary->rate_hz = data.rate_hz;
    summary->up_axis = data.metadata["ingest"]["original_up_axis"].get<std::string>()[0];
    summary->up_axis_reason = data.metadata["ingest"]["up_axis_reason"].get<std::string>();
    summary->gaps = std::move(gaps);
    const auto bvh = data.metadata.find("bvh");
    if (bvh != data.metadata.end() && bvh->contains("dropped_lead_frames")) {
      summary->dropped_lead_frames = bvh->at("dropped_lead_frames").get<int64_t>();
      summary->dropped_ease_in_frames = bvh->at("dropped_ease_in_frames").get<int64_t>();
      summary->dropped_teleport_frames = bvh->value("dropped_teleport_frames", int64_t{0});
      summary->dropped_held_frames = bvh->value("dropped_held_frames", int64_t{0});
    }
  }
  return data;
}

}  // namespace syn
