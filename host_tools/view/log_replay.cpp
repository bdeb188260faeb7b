// The replay feed: a frame log read whole (host_tools/log's reader stops at
// the first damaged record, so what plays is the intact prefix), played on
// the wall clock x speed, paused, or set to a time by the page's scrubber.
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <deque>
#include <thread>
#include <vector>

#include "frame_message.hpp"
#include "hal/output/frame_log_reader.hpp"
#include "view_loop.hpp"

namespace sinew::view {

namespace {

constexpr size_t kHistorySteps = 240;
constexpr auto kSendInterval = std::chrono::milliseconds(33);

struct Replay {
  std::vector<hal::output::DecodedPose> frames;
  std::vector<double> time_s;  // per frame, since the first frame
};

// Applies "play", "pause", "speed X" or "seek T" to the playback state;
// true when it changed something the page shows.
bool apply_command(const std::string& command, PlaybackState* p) {
  if (command == "play") return p->playing = true, true;
  if (command == "pause") return p->playing = false, true;
  const auto arg = [&](const char* prefix, double* out) {
    const std::string pre(prefix);
    if (command.rfind(pre, 0) != 0) return false;
    char* end = nullptr;
    const double v = std::strtod(command.c_str() + pre.size(), &end);
    if (end == command.c_str() + pre.size() || !(v == v)) return false;
    *out = v;
    return true;
  };
  double v = 0;
  if (arg("speed ", &v) && v > 0 && v <= 100) return p->speed = v, true;
  if (arg("seek ", &v)) {
    p->time_s = v < p->start_s ? p->start_s : (v > p->end_s ? p->end_s : v);
    return true;
  }
  return false;
}

// The last frame at or before t.
size_t frame_at(const Replay& r, double t) {
  size_t lo = 0, hi = r.time_s.size();
  while (hi - lo > 1) {
    const size_t mid = (lo + hi) / 2;
    (r.time_s[mid] <= t + 1e-9 ? lo : hi) = mid;  // a time given in decimal seconds picks its own frame
  }
  return lo;
}

}  // namespace

int run_replay(const ViewContext& ctx, const std::string& log_path) {
  std::string error;
  hal::output::FrameLogReader reader;
  if (!reader.open(log_path, &error)) return std::fprintf(stderr, "sinew-view: %s\n", error.c_str()), 1;
  if (reader.shape().vertex_count == 0)
    return std::fprintf(stderr,
                        "sinew-view: %s carries no vertices (a recording): render it first with sinew-log render\n",
                        log_path.c_str()),
           1;
  Replay replay;
  PeriodEstimate period;
  hal::output::DecodedPose pose;
  while (reader.next(&pose)) {
    if (replay.frames.empty() || pose.timestamp_ns >= replay.frames.front().timestamp_ns)
      replay.time_s.push_back(replay.frames.empty()
                                  ? 0.0
                                  : static_cast<double>(pose.timestamp_ns - replay.frames.front().timestamp_ns) * 1e-9);
    else
      replay.time_s.push_back(replay.time_s.back());
    period.add(pose);
    replay.frames.push_back(pose);
  }
  if (!reader.clean_end())
    std::fprintf(stderr, "sinew-view: %s: %s\n", log_path.c_str(), reader.stop_message().c_str());
  if (replay.frames.empty()) return std::fprintf(stderr, "sinew-view: %s has no intact frame\n", log_path.c_str()), 1;
  std::fprintf(stderr, "sinew-view: replaying %zu frames of %s (%.3f s)\n", replay.frames.size(), log_path.c_str(),
               replay.time_s.back());

  ShadowPipeline shadow;
  if (!shadow.init(*ctx.rig, ctx.options, &error)) return std::fprintf(stderr, "sinew-view: %s\n", error.c_str()), 1;
  PlaybackState playback;
  playback.replay = true;
  playback.playing = true;  // a page that only loads sees the run move
  playback.end_s = replay.time_s.back();
  StreamCounters counters;
  counters.frames = replay.frames.size();
  std::deque<ShadowStep> history;
  const std::string mismatch = rig_stream_mismatch(*ctx.rig, replay.frames.front());
  if (!mismatch.empty()) counters.mismatched = replay.frames.size();
  size_t stepped = 0;  // frames [0, stepped) are in the shadow pipeline's state
  bool dirty = true;
  auto last_send = std::chrono::steady_clock::now() - kSendInterval;
  auto last_clock = std::chrono::steady_clock::now();
  size_t shown = SIZE_MAX;
  while (*ctx.stop == 0) {
    const auto now = std::chrono::steady_clock::now();
    const double wall_s = std::chrono::duration<double>(now - last_clock).count();
    last_clock = now;
    for (const std::string& c : ctx.server->take_commands()) dirty |= apply_command(c, &playback);
    if (ctx.server->take_new_pages()) dirty = true;
    if (ctx.server->pages() == 0) {
      // Nobody watching: the replay waits (re-stepping the layers costs a
      // core), and a page that connects starts where it stopped.
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
      continue;
    }
    if (playback.playing) {
      playback.time_s += wall_s * playback.speed;
      if (playback.time_s > playback.end_s) playback.time_s = playback.start_s;  // loops
    }
    const size_t target = frame_at(replay, playback.time_s);
    if (target != shown) dirty = true;
    if (!dirty || now - last_send < kSendInterval) {
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
      continue;
    }
    if (mismatch.empty()) {
      // The layers' state at `target` is the state after stepping every frame
      // before it, from the start (as sinew-log render reproduces a run).
      if (target + 1 < stepped) {
        if (!shadow.reset(&error)) return std::fprintf(stderr, "sinew-view: %s\n", error.c_str()), 1;
        stepped = 0;
        history.clear();
      }
      for (; stepped <= target; ++stepped) {
        const hal::output::DecodedPose& f = replay.frames[stepped];
        history.push_back(shadow.step_frame(f));
        if (history.size() > kHistorySteps) history.pop_front();
      }
    }
    last_send = now;
    dirty = false;
    shown = target;
    playback.frame_time_s = replay.time_s[target];
    mark_held_inputs(replay.frames[target], target > 0 ? &replay.frames[target - 1] : nullptr, &counters.input_held);
    ctx.server->broadcast(frame_message(*ctx.rig, replay.frames[target], mismatch.empty() ? &shadow : nullptr, history,
                                        period.period_ns(ctx.tick_hz), playback, counters, mismatch));
  }
  return 0;
}

}  // namespace sinew::view
