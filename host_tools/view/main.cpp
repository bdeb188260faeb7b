// sinew-view: a web viewer of the deformed skin and its physics, live from
// the daemon's UDP stream or replayed from a frame log (docs/viewer.md).
//   sinew-view (--udp PORT | --log FILE) --rig FILE|NAME [--http-port P]
//              [--web-root DIR] [--tick-hz HZ] [--layers all|none|sph,metaballs,barnet,anatomy]
#include <unistd.h>

#include <CLI/CLI.hpp>
#include <csignal>
#include <cstdio>

#include "host_tools/run/pipeline_run.hpp"
#include "view_loop.hpp"

namespace {

volatile std::sig_atomic_t g_stop = 0;
void request_stop(int) { g_stop = 1; }

// The page's files: beside the executable, as the build lays them out.
std::string default_web_root() {
  char path[4096];
  const ssize_t n = ::readlink("/proc/self/exe", path, sizeof path - 1);
  if (n <= 0) return "web";
  std::string exe(path, static_cast<size_t>(n));
  return exe.substr(0, exe.rfind('/') + 1) + "web";
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"sinew-view: see the deformed skin and its physics in a browser"};
  uint16_t udp_port = 0, http_port = 8080;
  std::string log_path, rig_name, bind = "0.0.0.0", web_root = default_web_root(), layers = "all";
  uint32_t tick_hz = 0;
  auto* udp = app.add_option("--udp", udp_port, "receive the daemon's UDP stream on this port");
  auto* log = app.add_option("--log", log_path, "replay this frame log");
  udp->excludes(log);
  log->excludes(udp);
  app.add_option("--rig", rig_name, "the rig blob file, or a built-in rig (arm, hand)")->required();
  app.add_option("--http-port", http_port, "serve the page on http://127.0.0.1:PORT/");
  app.add_option("--bind", bind, "local address for the UDP stream (numeric)");
  app.add_option("--web-root", web_root, "the page's files (default: web/ beside the executable)");
  app.add_option("--tick-hz", tick_hz, "the tick budget's rate (0: from the frames' timestamps)");
  app.add_option("--layers", layers, "layers the viewer re-steps: all, none or a list (sph,metaballs,barnet,anatomy)");
  CLI11_PARSE(app, argc, argv);
  if (udp->count() == 0 && log->count() == 0) {
    std::fprintf(stderr, "sinew-view: give --udp PORT or --log FILE\n");
    return 2;
  }
  sinew::view::ViewContext ctx;
  std::string error;
  if (!sinew::run::parse_layer_list(layers, &ctx.options, &error)) {
    std::fprintf(stderr, "sinew-view: %s\n", error.c_str());
    return 2;
  }
  sinew::view::ViewRig rig;
  if (!sinew::view::load_view_rig(rig_name, &rig, &error)) {
    std::fprintf(stderr, "sinew-view: %s\n", error.c_str());
    return 2;
  }
  sinew::view::WebServer server;
  if (!server.start(web_root, http_port, sinew::view::rig_message_json(rig, tick_hz), &error)) {
    std::fprintf(stderr, "sinew-view: %s\n", error.c_str());
    return 1;
  }
  std::signal(SIGINT, request_stop);
  std::signal(SIGTERM, request_stop);
  std::fprintf(stderr, "sinew-view: rig %s (%s), page at http://127.0.0.1:%u/\n", rig_name.c_str(),
               sinew::firmware::describe_layers(rig.loaded).c_str(), http_port);
  ctx.rig = &rig;
  ctx.server = &server;
  ctx.tick_hz = tick_hz;
  ctx.options.tick_hz = tick_hz;  // the layers step at the stream's rate (else taken from the frames)
  ctx.stop = &g_stop;
  const int status =
      log->count() > 0 ? sinew::view::run_replay(ctx, log_path) : sinew::view::run_live(ctx, bind, udp_port);
  server.stop();
  return status;
}
