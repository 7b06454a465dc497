#include "tools/studio/studio_options.h"

namespace syn {

bool StudioOptions::IsValid(std::string* error) const {
  auto fail = [&](const std::string& message) {
    if (error) *error = message;
    return false;
  };
  if (host.empty()) return fail("--host must name an address (127.0.0.1: this machine only)");
  if (port < 0 || port > 65535) return fail("--port must lie in [0, 65535] (0: any free port)");
  if (max_body_bytes < 64) return fail("--max-body-bytes must be at least 64");
  if (!(max_motion_seconds > 0)) return fail("--max-motion-seconds must be positive");
  if (max_pieces < 1) return fail("--max-pieces must be at least 1");
  if (max_steps < 1) return fail("--max-steps must be at least 1");
  if (io_timeout_seconds < 1) return fail("--io-timeout must be at least 1 s");
  if (!(eval_rate > 0)) return fail("--eval-rate must be positive");
  if (!(sliding.contact_height >= 0) || !(sliding.slide_speed >= 0) || !(sliding.window >= 0) ||
      !(sliding.penetration >= 0)) {
    return fail("--contact-height, --slide-speed, --slide-window and --penetration must be >= 0");
  }
  return true;
}

nlohmann::json StudioOptions::ToJson() const {
  return {{"max_body_bytes", max_body_bytes},
          {"max_motion_seconds", max_motion_seconds},
          {"max_pieces", max_pieces},
          {"max_steps", max_steps},
          {"eval_rate", eval_rate},
          {"contact_height", sliding.contact_height},
          {"slide_speed", sliding.slide_speed},
          {"slide_window", sliding.window},
          {"penetration", sliding.penetration}};
}

}  // namespace syn
