// Sinks off the tick thread: the ring copies frames (the tick's buffers can
// change at once), keeps their order, refuses when full; the queued sink
// never blocks write() on a stalled sink in live runs (it drops and counts),
// loses nothing when lossless, and writes what is queued at close.
#include "firmware/runtime/async_sink.hpp"

#include <gtest/gtest.h>

#include <chrono>
#include <condition_variable>
#include <cstdlib>
#include <cstring>
#include <mutex>
#include <thread>
#include <vector>

#include "tests/support/alloc_guard.hpp"

namespace fw = sinew::firmware;
namespace hal = sinew::hal;

namespace {

// A frame of 4 vertices and 2 inputs whose every value derives from its tick.
struct TickFrame {
  explicit TickFrame(uint64_t tick) { set(tick); }
  void set(uint64_t tick) {
    for (int c = 0; c < 3; ++c)
      for (int v = 0; v < 4; ++v) pos[c][v] = static_cast<int32_t>(tick * 100 + static_cast<uint64_t>(c * 10 + v));
    inputs[0] = static_cast<int32_t>(tick);
    inputs[1] = -static_cast<int32_t>(tick);
    status[0] = static_cast<uint8_t>(tick & 0xF);
    frame.tick = tick;
    frame.timestamp_ns = tick * 1000;
    frame.vertex_count = 4;
    frame.input_count = 2;
    for (int c = 0; c < 3; ++c) frame.position[c] = pos[c];
    frame.input_value = inputs;
    frame.input_status = status;
  }
  int32_t pos[3][4] = {};
  int32_t inputs[2] = {};
  uint8_t status[2] = {};
  hal::PoseFrame frame;
};

bool frame_is_tick(const hal::PoseFrame& f, uint64_t tick) {
  const TickFrame want(tick);
  if (f.tick != tick || f.timestamp_ns != tick * 1000 || f.vertex_count != 4 || f.input_count != 2) return false;
  for (int c = 0; c < 3; ++c)
    for (int v = 0; v < 4; ++v)
      if (f.position[c][v] != want.pos[c][v]) return false;
  return f.input_value[0] == want.inputs[0] && f.input_value[1] == want.inputs[1] &&
         f.input_status[0] == want.status[0];
}

constexpr fw::FrameDims kDims{4, 2, false};

// Records the ticks it is given (checking every value); can be held shut
// to stand in for a stalled disk, and can fail writes.
class GateSink final : public fw::OutputSink {
 public:
  GateSink() { ticks.reserve(100000); }
  const char* name() const override { return "gate"; }
  bool write(const hal::PoseFrame& f) override {
    std::unique_lock<std::mutex> lock(mutex);
    cv.wait(lock, [&] { return open; });
    ticks.push_back(f.tick);
    if (!frame_is_tick(f, f.tick)) ++corrupt;
    return !fail;
  }
  void flush() override {}
  std::string status_line() const override { return "gate"; }
  void set_open(bool o) {
    {
      const std::lock_guard<std::mutex> lock(mutex);
      open = o;
    }
    cv.notify_all();
  }
  std::mutex mutex;
  std::condition_variable cv;
  bool open = true;
  bool fail = false;
  std::vector<uint64_t> ticks;
  uint64_t corrupt = 0;
};

}  // namespace

TEST(FrameRing, CopiesKeepsOrderAndRefusesWhenFull) {
  fw::FrameRing ring;
  ring.init(3, kDims);
  TickFrame f(0);
  for (uint64_t t = 0; t < 3; ++t) {
    f.set(t);
    EXPECT_TRUE(ring.try_push(f.frame));
  }
  f.set(99);  // the producer's buffers change: the ring holds copies
  EXPECT_FALSE(ring.try_push(f.frame));
  for (uint64_t t = 0; t < 3; ++t) {
    const hal::PoseFrame* got = ring.front();
    ASSERT_NE(got, nullptr);
    EXPECT_TRUE(frame_is_tick(*got, t)) << t;
    ring.pop();
  }
  EXPECT_EQ(ring.front(), nullptr);
  // A frame larger than the slots is refused, not truncated.
  TickFrame big(5);
  big.frame.input_count = 3;
  EXPECT_FALSE(ring.try_push(big.frame));
}

// Stage times travel with the frame when the slots hold them, and are left
// out (not read past) when they hold fewer or none.
TEST(FrameRing, CopiesTheStageTimesItsSlotsHold) {
  const uint32_t stage_ns[3] = {11, 22, 33};
  hal::PoseFrame frame;
  frame.tick = 7;
  frame.stage_count = 3;
  frame.stage_ns = stage_ns;
  for (const uint32_t held : {0u, 2u, 3u, 5u}) {
    fw::FrameRing ring;
    ring.init(2, {0, 0, false, held});
    ASSERT_TRUE(ring.try_push(frame));
    const hal::PoseFrame* got = ring.front();
    ASSERT_NE(got, nullptr);
    EXPECT_EQ(got->stage_count, std::min(held, 3u));
    if (held == 0) EXPECT_EQ(got->stage_ns, nullptr);
    for (uint32_t s = 0; s < got->stage_count; ++s) {
      EXPECT_NE(got->stage_ns, stage_ns);  // a copy
      EXPECT_EQ(got->stage_ns[s], stage_ns[s]);
    }
  }
}

// Woken per frame, and polled every 0.1 ms (2 000 frames through 4 slots:
// 500 polls at least).
TEST(AsyncSink, LosslessDeliversEveryFrameInOrderThroughASmallRing) {
  for (const auto& [poll_ns, frames] : {std::pair<uint64_t, uint64_t>{0, 20000}, {100'000, 2000}}) {
    auto gate = std::make_unique<GateSink>();
    GateSink* g = gate.get();
    std::string report;
    fw::AsyncSink sink(std::move(gate), kDims, {4, true, 0, -1, poll_ns}, &report);
    TickFrame f(0);
    for (uint64_t t = 0; t < frames; ++t) {
      f.set(t);
      EXPECT_TRUE(sink.write(f.frame));
    }
    sink.close();
    ASSERT_EQ(g->ticks.size(), frames) << "poll_ns " << poll_ns;
    for (uint64_t t = 0; t < frames; ++t) ASSERT_EQ(g->ticks[t], t);
    EXPECT_EQ(g->corrupt, 0u);
    EXPECT_EQ(sink.ring_drops(), 0u);
  }
}

// A stalled sink (a sync taking seconds) must not stall the tick: with the
// sink held shut, write() keeps returning; frames beyond the ring are
// dropped and counted. Were write() to wait, this test would hang.
TEST(AsyncSink, AStalledSinkNeverBlocksTheTickFramesBeyondTheRingAreCounted) {
  auto gate = std::make_unique<GateSink>();
  GateSink* g = gate.get();
  g->set_open(false);
  std::string report;
  fw::AsyncSink sink(std::move(gate), kDims, {8, false, 0, -1}, &report);
  TickFrame f(0);
  uint64_t accepted = 0;
  for (uint64_t t = 0; t < 100; ++t) {
    f.set(t);
    accepted += sink.write(f.frame) ? 1 : 0;
  }
  // The ring's 8 slots, plus at most the one frame the I/O thread holds.
  EXPECT_GE(accepted, 8u);
  EXPECT_LE(accepted, 9u);
  EXPECT_EQ(sink.ring_drops(), 100u - accepted);
  g->set_open(true);
  sink.close();
  ASSERT_EQ(g->ticks.size(), accepted);
  for (uint64_t i = 0; i < accepted; ++i) EXPECT_EQ(g->ticks[i], i);  // the oldest are kept, in order
  EXPECT_EQ(g->corrupt, 0u);
  EXPECT_NE(sink.status_line().find("dropped when full " + std::to_string(100 - accepted)), std::string::npos)
      << sink.status_line();
}

TEST(AsyncSink, FailedWritesOfTheWrappedSinkAreCountedAsLost) {
  auto gate = std::make_unique<GateSink>();
  gate->fail = true;
  std::string report;
  fw::AsyncSink sink(std::move(gate), kDims, {16, true, 0, -1}, &report);
  TickFrame f(0);
  for (uint64_t t = 0; t < 10; ++t) {
    f.set(t);
    EXPECT_TRUE(sink.write(f.frame));
  }
  sink.close();
  EXPECT_EQ(sink.frames_lost_after_write(), 10u);
}

TEST(AsyncSink, WriteDoesNotAllocate) {
  std::string report;
  fw::AsyncSink sink(std::make_unique<GateSink>(), kDims, {64, true, 0, -1}, &report);
  TickFrame f(0);
  sinew::test::AllocationCounter counter;
  for (uint64_t t = 0; t < 5000; ++t) {
    f.set(t);
    sink.write(f.frame);
  }
  EXPECT_EQ(counter.allocations(), 0u);
  sink.close();
}

namespace {
// Waits until `sink` has been handed `count` frames; false after 30 s (a
// liveness bound: success returns as soon as the frames are there).
bool delivered_within_bound(GateSink& sink, size_t count) {
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  for (;;) {
    {
      const std::lock_guard<std::mutex> lock(sink.mutex);
      if (sink.ticks.size() >= count) return true;
    }
    if (std::chrono::steady_clock::now() >= deadline) return false;
    std::this_thread::sleep_for(std::chrono::microseconds(200));
  }
}
}  // namespace

// Polled I/O threads: the tick never wakes the I/O thread for a frame (no
// system call in write()), yet every frame leaves without close(); the
// per-frame mode wakes it (the figure the poll removes).
TEST(AsyncSink, PolledIoThreadDrainsWithoutBeingWoken) {
  for (const uint64_t poll_ns : {uint64_t{0}, uint64_t{500'000}}) {
    auto gate = std::make_unique<GateSink>();
    GateSink* g = gate.get();
    std::string report;
    fw::AsyncSinkOptions options;
    options.ring_frames = 64;
    options.poll_ns = poll_ns;
    fw::AsyncSink sink(std::move(gate), kDims, options, &report);
    TickFrame f(0);
    // Each frame once the previous one has left, so the I/O thread has run
    // dry between frames. The per-frame mode wakes the I/O thread only if it
    // already sleeps, which no fixed pause can promise on a loaded machine, so
    // frames go on (up to 10 000, within 30 s) until a wake-up was counted.
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);  // a liveness bound
    uint64_t frames = 0;
    while (frames < 40 ||
           (poll_ns == 0 && sink.wakes() == 0 && frames < 10000 && std::chrono::steady_clock::now() < deadline)) {
      f.set(frames);
      EXPECT_TRUE(sink.write(f.frame));
      ++frames;
      // Delivered without close(): the I/O thread drains on its own.
      ASSERT_TRUE(delivered_within_bound(*g, frames)) << "poll_ns " << poll_ns << ", frame " << frames - 1;
      std::this_thread::sleep_for(std::chrono::microseconds(200));  // room for the I/O thread to go to sleep
    }
    {
      const std::lock_guard<std::mutex> lock(g->mutex);
      ASSERT_EQ(g->ticks.size(), frames) << "poll_ns " << poll_ns;
      for (uint64_t t = 0; t < frames; ++t) EXPECT_EQ(g->ticks[t], t);
    }
    if (poll_ns > 0)
      EXPECT_EQ(sink.wakes(), 0u);
    else
      EXPECT_GT(sink.wakes(), 0u) << frames << " frames";
    sink.close();
    EXPECT_EQ(sink.ring_drops(), 0u);
  }
}

namespace {
// Says how many frames it has written, as the frame log and UDP sinks do.
class CountingStatusSink final : public fw::OutputSink {
 public:
  const char* name() const override { return "counting"; }
  bool write(const hal::PoseFrame&) override {
    ++written;
    return true;
  }
  void flush() override {}
  std::string status_line() const override { return "written " + std::to_string(written); }
  uint64_t written = 0;  // I/O thread only
};
}  // namespace

// The daemon's periodic statistics read status_line() without a flush; the
// wrapped sink's counters must be the running ones, not those at open.
TEST(AsyncSink, StatusFollowsTheWritesWithoutAFlush) {
  for (const uint64_t poll_ns : {uint64_t{0}, uint64_t{500'000}}) {
    std::string report;
    fw::AsyncSinkOptions options;
    options.poll_ns = poll_ns;
    // Lossless: an I/O thread held off the CPU longer than the ring lasts
    // (128 ms) would otherwise drop frames, and write() would say so. The
    // refresh under test does not depend on the mode.
    options.lossless = true;
    fw::AsyncSink sink(std::make_unique<CountingStatusSink>(), kDims, options, &report);
    EXPECT_EQ(sink.status_line().rfind("written 0;", 0), 0u) << sink.status_line();
    TickFrame f(0);
    // Frames for 1.5 s, one a millisecond: several refresh periods.
    uint64_t t = 0;
    for (; t < 1500; ++t) {
      f.set(t);
      EXPECT_TRUE(sink.write(f.frame));
      std::this_thread::sleep_for(std::chrono::milliseconds(1));
    }
    // An I/O thread delayed by load refreshes later, so frames go on, one every
    // 50 ms, until the line shows them (30 s: a liveness bound). Without the
    // refresh it would say "written 0" until the flush at close().
    const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    auto shown = [&] {
      const std::string line = sink.status_line();
      return std::strtoull(line.c_str() + std::strlen("written "), nullptr, 10);
    };
    while (shown() < 500 && std::chrono::steady_clock::now() < deadline) {
      f.set(t++);
      EXPECT_TRUE(sink.write(f.frame));
      std::this_thread::sleep_for(std::chrono::milliseconds(50));
    }
    EXPECT_GE(shown(), 500u) << "poll_ns " << poll_ns << ": " << sink.status_line();
    sink.close();
  }
}
