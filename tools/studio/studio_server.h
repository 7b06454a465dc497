// syn-studio's HTTP face (cpp-httplib): the page and its scripts, and the JSON API over tools/studio/studio.h.
//
//   GET  /                 the page (web/index.html), /studio.js, /studio.css; /player.js (the report's
//                          player) and /three.js (three.js from npm, wrapped as a classic script like the
//                          report's), all read once at start
//   GET  /api/library      styles, segments, durations and σ (Studio::library)
//   GET  /api/robot        the player's robot description
//   GET  /api/script       the --script file's text ("" without one), for the page to start from
//   POST /api/compose      body: a compose script's TOML → Studio::compose's JSON; a script that cannot be
//                          composed → 400 {"error": "script.toml:LINE: message"}; a body over
//                          --max-body-bytes → 413. Query `file=NAME` names the script in messages.
//   POST /api/parse        body: a script's TOML → Studio::parse's JSON (what the page edits), errors as above
//
// Each error is answered and the server keeps serving; socket reads and writes time out after
// --io-timeout seconds, and a composition is bounded by the Studio's limits.
#pragma once

#include <memory>
#include <string>

#include "tools/studio/studio.h"

namespace httplib {
class Server;
}

namespace syn {

// The page's files, read from disk at start (a missing one is a DataError naming it and what makes it).
struct StudioPage {
  std::string index_html, studio_js, studio_css, player_js, three_js;
  // web_root: tools/studio/web; report_root: tools/report (player.js, node_modules/three).
  static StudioPage Load(const std::string& web_root, const std::string& report_root);
};

class StudioServer {
 public:
  StudioServer(const Studio& studio, StudioPage page, std::string initial_script);
  ~StudioServer();
  // Binds options().host:port (port 0: any free one) and returns the port; throws DataError when it cannot.
  int bind();
  // Serves until stop() (from another thread or a signal handler's thread).
  void run();
  void stop();

 private:
  const Studio& studio_;
  StudioPage page_;
  std::string initial_script_;
  std::unique_ptr<httplib::Server> server_;
};

}  // namespace syn
