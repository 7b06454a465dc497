// syn-studio --library LIB.h5 --model ROBOT.urdf --robot-map MAP.toml [--port 8080] [--script FILE]:
// a local web app that composes motions from a synergy library while you edit them (tools/studio/).
#include <csignal>
#include <iostream>
#include <thread>

#include "common/cli.h"
#include "common/file_bytes.h"
#include "tools/studio/studio.h"
#include "tools/studio/studio_server.h"

int main(int argc, char** argv) {
  CLI::App app{"SynSculptor studio: compose motions from a synergy library in the browser. Pick a style and its "
               "segments, set each step's synergy coefficients (in units of the library's sigma), duration, "
               "repetitions and interpolation, and watch the robot play the result with its momentum, dP/dKE and "
               "foot-sliding plots and the joint-limit warnings of each step. The page loads and saves the TOML "
               "scripts syn-compose reads (manifests/scripts/README.md), composed here with syn-compose's and "
               "syn-evaluate's own code. Serves http://HOST:PORT/ until interrupted (Ctrl-C).",
               "syn-studio"};
  syn::CommonFlags common;
  syn::AddCommonFlags(app, common, /*with_output=*/false);
  syn::StudioOptions options;
  options.web_root = SYN_STUDIO_SOURCE_DIR "/tools/studio/web";
  options.report_root = SYN_STUDIO_SOURCE_DIR "/tools/report";
  std::string library_path, model_path, robot_map_path, script_path;
  app.add_option("--library", library_path, "Synergy library (syn-library, e.g. outputs/demo/library.h5)")->required();
  app.add_option("--model", model_path, "The robot URDF the library was made for; scripts must name this file")
      ->required();
  app.add_option("--robot-map", robot_map_path, "Robot map (its feet give the foot-sliding metric)")->required();
  app.add_option("--script", script_path, "A compose script to start from (else the page starts with one step)");
  app.add_option("--host", options.host, "Address to listen on (loopback: this machine only)")->capture_default_str();
  app.add_option("--port", options.port, "TCP port (0: any free port, printed at start)")->capture_default_str();
  app.add_option("--max-body-bytes", options.max_body_bytes, "Largest request body; larger ones get HTTP 413")
      ->capture_default_str();
  app.add_option("--max-motion-seconds", options.max_motion_seconds,
                 "Longest motion one request may compose (sum of repetitions x duration)")->capture_default_str();
  app.add_option("--max-pieces", options.max_pieces, "Most repetitions in all steps of one request")
      ->capture_default_str();
  app.add_option("--max-steps", options.max_steps, "Most steps in one request")->capture_default_str();
  app.add_option("--io-timeout", options.io_timeout_seconds, "Socket read/write timeout, s")->capture_default_str();
  app.add_option("--eval-rate", options.eval_rate,
                 "Metrics grid, Hz (syn-evaluate's default; lower it to speed up long motions)")->capture_default_str();
  app.add_option("--contact-height", options.sliding.contact_height, "Foot sliding: contact below this height, m")
      ->capture_default_str();
  app.add_option("--slide-speed", options.sliding.slide_speed, "Foot sliding: a foot in contact faster than this, m/s")
      ->capture_default_str();
  app.add_option("--slide-window", options.sliding.window, "Foot sliding: centred speed window, s")
      ->capture_default_str();
  app.add_option("--penetration", options.sliding.penetration, "Foot sliding: deeper than this below the ground, m")
      ->capture_default_str();
  app.add_option("--web-root", options.web_root, "The page's folder (index.html, studio.js, studio.css)")
      ->capture_default_str();
  app.add_option("--report-root", options.report_root,
                 "tools/report: player.js and node_modules/three (make report-npm)")->capture_default_str();
  return syn::RunTool(app, argc, argv, [&] {
    std::string error;
    if (!options.IsValid(&error)) throw syn::UsageError(error);
    // Signals go to the waiting thread below, not to httplib's workers.
    sigset_t signals;
    sigemptyset(&signals);
    sigaddset(&signals, SIGINT);
    sigaddset(&signals, SIGTERM);
    pthread_sigmask(SIG_BLOCK, &signals, nullptr);

    const syn::Studio studio(library_path, model_path, robot_map_path, options);
    syn::PrintWarnings("syn-studio", studio.modelWarnings());
    const std::string initial_script = script_path.empty() ? "" : syn::ReadFileText(script_path);
    syn::StudioServer server(studio, syn::StudioPage::Load(options.web_root, options.report_root), initial_script);
    const int port = server.bind();
    std::cerr << "syn-studio: serving " << library_path << " on http://" << options.host << ":" << port
              << "/ (Ctrl-C stops)" << std::endl;
    std::thread waiter([&] {
      int signal = 0;
      sigwait(&signals, &signal);
      server.stop();
    });
    server.run();
    // run() also returns when listening fails: wake the waiter so that it can be joined.
    pthread_kill(waiter.native_handle(), SIGTERM);
    waiter.join();
    std::cerr << "syn-studio: stopped" << std::endl;
  });
}
