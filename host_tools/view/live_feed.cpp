// The live feed: the daemon's UDP stream (host_tools/receiver reassembles it).
#include <chrono>
#include <cstdio>
#include <deque>

#include "frame_message.hpp"
#include "host_tools/receiver/udp_receiver.hpp"
#include "view_loop.hpp"

namespace sinew::view {

namespace {

constexpr size_t kHistorySteps = 240;
constexpr auto kSendInterval = std::chrono::milliseconds(33);

}  // namespace

int run_live(const ViewContext& ctx, const std::string& bind_address, uint16_t udp_port) {
  receiver::UdpReceiverOptions options;
  options.bind_address = bind_address;
  options.port = udp_port;
  receiver::UdpReceiver udp;
  std::string error;
  if (!udp.open(options, &error)) return std::fprintf(stderr, "sinew-view: %s\n", error.c_str()), 1;
  ShadowPipeline shadow;
  if (!shadow.init(*ctx.rig, ctx.options, &error)) return std::fprintf(stderr, "sinew-view: %s\n", error.c_str()), 1;
  std::fprintf(stderr, "sinew-view: listening for the UDP stream on %s:%u\n", bind_address.c_str(), udp.port());

  PlaybackState playback;
  StreamCounters counters;
  PeriodEstimate period;
  std::deque<ShadowStep> history;
  hal::output::DecodedPose pose, previous;
  bool have_frame = false, fits = false, dirty = false;
  uint64_t last_tick = 0;
  std::string mismatch;
  auto last_send = std::chrono::steady_clock::now() - kSendInterval;
  while (*ctx.stop == 0) {
    const receiver::ReceiveResult r = udp.receive(10, &pose, &error);
    if (r == receiver::ReceiveResult::kError) return std::fprintf(stderr, "sinew-view: %s\n", error.c_str()), 1;
    if (r == receiver::ReceiveResult::kFrame) {
      ++counters.frames;
      mark_held_inputs(pose, have_frame ? &previous : nullptr, &counters.input_held);
      counters.frames_lost = udp.stats().frames_lost;
      mismatch = rig_stream_mismatch(*ctx.rig, pose);
      fits = mismatch.empty();
      if (!fits) {
        ++counters.mismatched;
      } else {
        // A lower tick: the daemon restarted; its layers start from rest.
        if (have_frame && pose.tick <= last_tick && !shadow.reset(&error))
          return std::fprintf(stderr, "sinew-view: %s\n", error.c_str()), 1;
        period.add(pose);
        history.push_back(shadow.step_frame(pose));
        if (history.size() > kHistorySteps) history.pop_front();
        last_tick = pose.tick;
      }
      have_frame = true;
      dirty = true;
      previous.tick = pose.tick;
      previous.input_count = pose.input_count;
      previous.input_value = pose.input_value;
    }
    (void)ctx.server->take_commands();  // play, pause, seek: replay only
    if (ctx.server->take_new_pages()) dirty = true;
    const auto now = std::chrono::steady_clock::now();
    if (!dirty || now - last_send < kSendInterval) continue;
    last_send = now;
    dirty = false;
    if (!have_frame)
      ctx.server->broadcast(status_message(playback, counters, ""));
    else
      ctx.server->broadcast(frame_message(*ctx.rig, pose, fits ? &shadow : nullptr, history,
                                          period.period_ns(ctx.tick_hz), playback, counters, mismatch));
  }
  std::fprintf(stderr, "sinew-view: %s\n", udp.summary().c_str());
  return 0;
}

}  // namespace sinew::view
