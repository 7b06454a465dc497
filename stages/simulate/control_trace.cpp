#include "stages/simulate/control_trace.h"

#include <cstdio>

namespace syn {
namespace {

constexpr const char* kHeader =
    "time,frame,balancing,com_x,com_y,capture_error_x,capture_error_y,plan_zmp_x,plan_zmp_y,wanted_zmp_x,wanted_zmp_y,"
    "commanded_zmp_x,commanded_zmp_y,level_force_x,level_force_y,level_force_z,planned_force_x,planned_force_y,"
    "planned_force_z,applied_force_x,applied_force_y,applied_force_z,unexplained_moment_x,unexplained_moment_y,"
    "unexplained_moment_z,unexplained_force_x,unexplained_force_y,unexplained_force_z,landing_needed\n";

// %.9g: enough digits to tell a 1 kHz step's time and a millinewton apart, few enough to keep a 40 s take's
// trace near 10 MB.
void Append(std::string& out, double value) {
  char buffer[32];
  const int length = std::snprintf(buffer, sizeof(buffer), ",%.9g", value);
  out.append(buffer, static_cast<size_t>(length));
}

void Append(std::string& out, const double* values, int count) {
  for (int i = 0; i < count; ++i) Append(out, values[i]);
}

}  // namespace

std::string ControlTrace::ToCsv() const {
  std::string out = kHeader;
  out.reserve(out.size() + rows_.size() * 320);
  char buffer[64];
  for (const ControlTraceRow& row : rows_) {
    const int length = std::snprintf(buffer, sizeof(buffer), "%.9g,%lld,%d", row.time, static_cast<long long>(row.frame),
                                     row.balancing ? 1 : 0);
    out.append(buffer, static_cast<size_t>(length));
    Append(out, row.level.com.data(), 2);
    Append(out, row.level.capture_error.data(), 2);
    Append(out, row.level.plan_zmp.data(), 2);
    Append(out, row.level.wanted_zmp.data(), 2);
    Append(out, row.level.commanded_zmp.data(), 2);
    Append(out, row.level.force.data(), 3);
    Append(out, row.planned_force.data(), 3);
    Append(out, row.applied_force.data(), 3);
    Append(out, row.unexplained.data(), 6);
    Append(out, row.landing_needed);
    out.push_back('\n');
  }
  return out;
}

}  // namespace syn
