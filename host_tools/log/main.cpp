// sinew-log: reads the daemon's frame logs (docs/frame-formats.md).
//   sinew-log verify FILE...   checks every record and the stream's order;
//                              exit 0 when every file is intact, 1 if not
//   sinew-log dump FILE        one line per frame: tick, time, inputs and
//                              the first vertices in metres
//   sinew-log render RECORDING --rig RIG -o OUT.log [--normals] [--every-n-frames N]
//                              regenerates a recorded run's full frames
// Exit 2: a file that cannot be opened or is not a frame log, or bad usage.
#include <CLI/CLI.hpp>
#include <cinttypes>
#include <cmath>
#include <cstdio>

#include "log_check.hpp"
#include "render.hpp"

namespace {

namespace out = sinew::hal::output;

// Status bits as letters: c clamped, s stale, r rejected, y yielded.
std::string status_letters(uint8_t s) {
  std::string t;
  const char letters[] = {'c', 's', 'r', 'y'};
  for (int bit = 0; bit < 4; ++bit)
    if (s & (1u << bit)) t += letters[bit];
  return t;
}

int dump(const std::string& path, uint64_t from_tick, uint64_t count, uint32_t vertices) {
  out::FrameLogReader reader;
  std::string error;
  if (!reader.open(path, &error)) {
    std::fprintf(stderr, "sinew-log: %s\n", error.c_str());
    return 2;
  }
  const out::FrameShape& shape = reader.shape();
  // Positions are Q12.20 rig units; one rig unit is 2^e metres.
  const double metres_per_lsb = std::ldexp(1.0, shape.length_exponent - 20);
  vertices = std::min(vertices, shape.vertex_count);
  std::printf("# tick timestamp_ns inputs[value/status] ");
  for (uint32_t v = 0; v < vertices; ++v) std::printf("v%u(x,y,z m) ", v);
  std::printf("\n");
  out::DecodedPose pose;
  uint64_t printed = 0;
  while (printed < count && reader.next(&pose)) {
    if (pose.tick < from_tick) continue;
    std::printf("%" PRIu64 " %" PRIu64 " [", pose.tick, pose.timestamp_ns);
    for (uint32_t i = 0; i < pose.input_count; ++i)
      std::printf("%s%d%s%s", i ? " " : "", pose.input_value[i], pose.input_status[i] ? "/" : "",
                  status_letters(pose.input_status[i]).c_str());
    std::printf("]");
    for (uint32_t v = 0; v < vertices; ++v)
      std::printf(" (%.6f,%.6f,%.6f)", pose.position[0][v] * metres_per_lsb, pose.position[1][v] * metres_per_lsb,
                  pose.position[2][v] * metres_per_lsb);
    std::printf("\n");
    ++printed;
  }
  if (printed < count && !reader.clean_end()) {
    std::fprintf(stderr, "sinew-log: %s: %s\n", path.c_str(), reader.stop_message().c_str());
    return 1;
  }
  return std::ferror(stdout) ? 1 : 0;
}

int verify(const std::vector<std::string>& paths) {
  int status = 0;
  for (const std::string& path : paths) {
    sinew::log_tool::LogCheck check;
    std::string error;
    if (!sinew::log_tool::check_log(path, &check, &error)) {
      std::fprintf(stderr, "sinew-log: %s\n", error.c_str());
      status = 2;
      continue;
    }
    std::fputs(sinew::log_tool::describe(path, check).c_str(), stdout);
    if (!check.ok() && status == 0) status = 1;
  }
  return status;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "Reads sinewd's frame logs: verify checks them, dump prints their frames, render regenerates a recording's"};
  app.require_subcommand(1);
  std::vector<std::string> verify_paths;
  CLI::App* verify_cmd = app.add_subcommand("verify", "check every record and the order of ticks and timestamps");
  verify_cmd->add_option("files", verify_paths, "frame logs")->required()->check(CLI::ExistingFile);
  std::string dump_path;
  uint64_t from_tick = 0, count = UINT64_MAX;
  uint32_t vertices = 3;
  CLI::App* dump_cmd = app.add_subcommand("dump", "print frames: tick, time, inputs, first vertices in metres");
  dump_cmd->add_option("file", dump_path, "a frame log")->required()->check(CLI::ExistingFile);
  dump_cmd->add_option("--from", from_tick, "first tick to print");
  dump_cmd->add_option("--count", count, "frames to print")->check(CLI::Range(uint64_t{1}, UINT64_MAX));
  dump_cmd->add_option("--vertices", vertices, "vertices per frame")->check(CLI::Range(0u, 1000000u));
  sinew::log_tool::RenderOptions render;
  CLI::App* render_cmd =
      app.add_subcommand("render", "regenerate the full frames of a recording (a `record` sink's log)");
  render_cmd->add_option("recording", render.recording, "a recording")->required()->check(CLI::ExistingFile);
  render_cmd->add_option("--rig", render.rig, "the run's rig: builtin:arm, builtin:hand or a blob file")->required();
  render_cmd->add_option("-o,--out", render.out, "the frame log to write (must not exist)")->required();
  render_cmd->add_flag("--normals", render.normals, "include normals (as the log sink's `normals`)");
  render_cmd->add_option("--every-n-frames", render.every_n_frames, "keep ticks that are multiples of N")
      ->check(CLI::Range(uint64_t{1}, uint64_t{1000000}));
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e) == 0 ? 0 : 2;
  }
  if (*verify_cmd) return verify(verify_paths);
  if (*render_cmd) {
    sinew::log_tool::RenderResult result;
    std::string error;
    if (!sinew::log_tool::render_recording(render, &result, &error)) {
      std::fprintf(stderr, "sinew-log: %s\n", error.c_str());
      return 2;
    }
    std::printf("%s: %llu frames rendered from %llu recorded ticks\n", render.out.c_str(),
                static_cast<unsigned long long>(result.frames_written),
                static_cast<unsigned long long>(result.frames_read));
    if (!result.recording_intact) {
      std::fprintf(stderr, "sinew-log: %s: %s (rendered up to it)\n", render.recording.c_str(),
                   result.recording_stop.c_str());
      return 1;
    }
    return 0;
  }
  return dump(dump_path, from_tick, count, vertices);
}
