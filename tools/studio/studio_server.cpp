#include "tools/studio/studio_server.h"

#include <filesystem>

// After studio_server.h (Eigen): httplib.h includes <resolv.h>, whose `_res` macro breaks Eigen headers that
// come after it.
#include <httplib.h>

#include "common/error.h"
#include "common/file_bytes.h"

namespace syn {
namespace {

std::string ReadPageFile(const std::filesystem::path& path, const std::string& made_by) {
  if (!std::filesystem::is_regular_file(path)) {
    throw DataError(Location::InFile(path.string()), "missing: " + made_by);
  }
  return ReadFileText(path.string());
}

void SendJson(httplib::Response& response, int status, const nlohmann::json& body) {
  response.status = status;
  response.set_content(body.dump(), "application/json");
}

// A script's name in error messages: letters, digits and ._- only (it is echoed back).
std::string ScriptName(const httplib::Request& request) {
  std::string name = request.has_param("file") ? request.get_param_value("file") : "";
  for (char c : name) {
    if (!std::isalnum(static_cast<unsigned char>(c)) && c != '.' && c != '_' && c != '-') return "script.toml";
  }
  return name.empty() || name.size() > 100 ? "script.toml" : name;
}

}  // namespace

StudioPage StudioPage::Load(const std::string& web_root, const std::string& report_root) {
  const std::filesystem::path web(web_root), report(report_root);
  StudioPage page;
  page.index_html = ReadPageFile(web / "index.html", "the studio's page (tools/studio/web; --web-root)");
  page.studio_js = ReadPageFile(web / "studio.js", "the studio's page (tools/studio/web; --web-root)");
  page.studio_css = ReadPageFile(web / "studio.css", "the studio's page (tools/studio/web; --web-root)");
  page.player_js = ReadPageFile(report / "player.js", "the report's 3-D player (tools/report; --report-root)");
  const std::string three = ReadPageFile(report / "node_modules" / "three" / "build" / "three.cjs",
                                         "three.js from npm: run `make report-npm` (--report-root)");
  // The CommonJS build inside a function scope, as tools/report/page.py wraps it: player.js expects a global THREE.
  page.three_js = "/* three.js, MIT licence, from npm (tools/report/package-lock.json), wrapped as a classic script by "
                  "syn-studio. */\nvar THREE = (function () { var exports = {}; var module = { exports: exports };\n" +
                  three + "\nreturn exports; })();\n";
  return page;
}

StudioServer::StudioServer(const Studio& studio, StudioPage page, std::string initial_script)
    : studio_(studio), page_(std::move(page)), initial_script_(std::move(initial_script)),
      server_(std::make_unique<httplib::Server>()) {
  const StudioOptions& options = studio_.options();
  server_->set_payload_max_length(options.max_body_bytes);
  server_->set_read_timeout(options.io_timeout_seconds, 0);
  server_->set_write_timeout(options.io_timeout_seconds, 0);
  server_->set_keep_alive_timeout(options.io_timeout_seconds);

  auto file = [this](const char* path, const std::string* content, const char* type) {
    server_->Get(path, [content, type](const httplib::Request&, httplib::Response& response) {
      response.set_content(*content, type);
    });
  };
  file("/", &page_.index_html, "text/html; charset=utf-8");
  file("/index.html", &page_.index_html, "text/html; charset=utf-8");
  file("/studio.js", &page_.studio_js, "text/javascript; charset=utf-8");
  file("/studio.css", &page_.studio_css, "text/css; charset=utf-8");
  file("/player.js", &page_.player_js, "text/javascript; charset=utf-8");
  file("/three.js", &page_.three_js, "text/javascript; charset=utf-8");
  file("/api/script", &initial_script_, "text/plain; charset=utf-8");
  server_->Get("/api/library", [this](const httplib::Request&, httplib::Response& response) {
    SendJson(response, 200, studio_.library());
  });
  server_->Get("/api/robot", [this](const httplib::Request&, httplib::Response& response) {
    SendJson(response, 200, studio_.robot());
  });
  server_->Post("/api/compose", [this](const httplib::Request& request, httplib::Response& response) {
    try {
      SendJson(response, 200, studio_.compose(request.body, ScriptName(request)));
    } catch (const DataError& error) {
      SendJson(response, 400, {{"error", error.what()}});
    }
  });
  server_->Post("/api/parse", [this](const httplib::Request& request, httplib::Response& response) {
    try {
      SendJson(response, 200, studio_.parse(request.body, ScriptName(request)));
    } catch (const DataError& error) {
      SendJson(response, 400, {{"error", error.what()}});
    }
  });
  // Anything else a handler throws is a bug, answered as one; the server goes on.
  server_->set_exception_handler([](const httplib::Request&, httplib::Response& response, std::exception_ptr thrown) {
    std::string what = "unknown exception";
    try {
      std::rethrow_exception(thrown);
    } catch (const std::exception& error) {
      what = error.what();
    } catch (...) {
    }
    SendJson(response, 500, {{"error", "internal error (please report): " + what}});
  });
  // Errors httplib answers itself (404, 413 for a body over --max-body-bytes, 400 for a malformed request)
  // get a message too.
  server_->set_error_handler([max = options.max_body_bytes](const httplib::Request& request, httplib::Response& response) {
    if (!response.body.empty()) return;
    std::string message = "HTTP " + std::to_string(response.status);
    if (response.status == 413) message = "request body larger than --max-body-bytes = " + std::to_string(max);
    if (response.status == 404) message = "no such page: " + request.path;
    SendJson(response, response.status, {{"error", message}});
  });
}

StudioServer::~StudioServer() = default;

int StudioServer::bind() {
  const StudioOptions& options = studio_.options();
  const int port = options.port == 0 ? server_->bind_to_any_port(options.host)
                                     : (server_->bind_to_port(options.host, options.port) ? options.port : -1);
  if (port <= 0) {
    throw DataError(Location::InFile(options.host + ":" + std::to_string(options.port)),
                    "cannot listen there (port in use? --port)");
  }
  return port;
}

void StudioServer::run() { server_->listen_after_bind(); }

void StudioServer::stop() { server_->stop(); }

}  // namespace syn
