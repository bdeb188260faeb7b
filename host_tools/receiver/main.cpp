// sinew-receive: receives a sinew UDP pose stream, reassembles and checks its
// frames, and reports losses; optionally writes the frames as CSV.
//   sinew-receive --port P [--count N] [--csv out.csv] [--vertices]
//                 [--bind ADDR] [--stream ID] [--timeout S] [--quiet]
#include <CLI/CLI.hpp>
#include <cinttypes>
#include <csignal>
#include <cstdio>

#include "csv_writer.hpp"
#include "udp_receiver.hpp"

namespace {

volatile std::sig_atomic_t g_stop = 0;
void request_stop(int) { g_stop = 1; }

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"sinew-receive: receive a sinew UDP pose stream"};
  sinew::receiver::UdpReceiverOptions options;
  uint64_t count = 0;
  std::string csv_path;
  bool vertices = false;
  bool quiet = false;
  double timeout_s = 0;
  app.add_option("--port", options.port, "UDP port to listen on")->required();
  app.add_option("--bind", options.bind_address, "local address to bind (numeric)");
  app.add_option("--count", count, "stop after this many frames (0: until interrupted)");
  app.add_option("--csv", csv_path, "write one CSV row per frame to this file");
  app.add_flag("--vertices", vertices, "include every vertex position in the CSV rows");
  app.add_option("--stream", options.reassembly.stream_id, "accept only this stream id (0: any)");
  app.add_option("--timeout", timeout_s, "stop after this many seconds without a frame (0: never)")
      ->check(CLI::NonNegativeNumber);
  app.add_flag("--quiet", quiet, "no line per frame");
  CLI11_PARSE(app, argc, argv);

  std::signal(SIGINT, request_stop);
  std::signal(SIGTERM, request_stop);

  sinew::receiver::UdpReceiver receiver;
  std::string error;
  if (!receiver.open(options, &error)) {
    std::fprintf(stderr, "sinew-receive: %s\n", error.c_str());
    return 1;
  }
  sinew::receiver::CsvWriter csv;
  if (!csv_path.empty() && !csv.open(csv_path, vertices, &error)) {
    std::fprintf(stderr, "sinew-receive: %s\n", error.c_str());
    return 1;
  }
  std::fprintf(stderr, "sinew-receive: listening on %s:%u\n", options.bind_address.c_str(), receiver.port());

  // Short polls so an interrupt or the idle timeout is noticed promptly.
  constexpr int kPollMs = 200;
  const auto idle_limit_ms = static_cast<int64_t>(timeout_s * 1000);
  int64_t idle_ms = 0;
  uint64_t frames = 0;
  int status = 0;
  sinew::hal::output::DecodedPose pose;
  while (g_stop == 0 && (count == 0 || frames < count)) {
    const auto r = receiver.receive(kPollMs, &pose, &error);
    if (r == sinew::receiver::ReceiveResult::kError) {
      std::fprintf(stderr, "sinew-receive: %s\n", error.c_str());
      status = 1;
      break;
    }
    if (r == sinew::receiver::ReceiveResult::kTimeout) {
      idle_ms += kPollMs;
      if (idle_limit_ms > 0 && idle_ms >= idle_limit_ms) {
        std::fprintf(stderr, "sinew-receive: no frame for %.1f s\n", timeout_s);
        status = count == 0 ? 0 : 2;  // fewer frames than asked for
        break;
      }
      continue;
    }
    idle_ms = 0;
    ++frames;
    if (!quiet)
      std::printf("frame seq %" PRIu64 " tick %" PRIu64 " vertices %" PRIu32 " inputs %" PRIu32 "\n",
                  receiver.sequence(), pose.tick, pose.vertex_count, pose.input_count);
    if (!csv_path.empty()) csv.write(receiver.sequence(), pose);
  }
  std::fflush(stdout);
  if (!csv_path.empty()) {
    if (!csv.close()) {
      std::fprintf(stderr, "sinew-receive: error writing %s\n", csv_path.c_str());
      status = 1;
    }
    if (csv.skipped() > 0)
      std::fprintf(stderr, "sinew-receive: %" PRIu64 " frames with other counts than the first were not written\n",
                   csv.skipped());
  }
  std::fprintf(stderr, "sinew-receive: %s\n", receiver.summary().c_str());
  return status;
}
