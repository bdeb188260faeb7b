// GpioSource on the simulated twin: encoders through latch(), index homing,
// limit switches, sync, fault output, errors, and no allocation per tick.
#include "hal/gpio/gpio_source.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cerrno>
#include <cstdio>
#include <vector>

#include "hal/common/input_health.hpp"
#include "hal/gpio/simulated_gpio.hpp"
#include "tests/support/alloc_guard.hpp"
#include "tests/support/time_units.hpp"

namespace sinew::hal::gpio {
namespace {

using sinew::test::kMs;
using sinew::test::kUs;

// Plays an encoder on two lines of the wire: quarter-period steps at a fixed spacing.
struct EncoderDriver {
  SimulatedGpio* wire;
  uint32_t a, b;
  int pos = 0;  // index into kQuadratureForward
  // Steps and latches every 8 quarter periods (4 edges per line), as a
  // ticking runtime would: the v1 kernel FIFO holds only 16 events per line.
  template <typename F>
  void run(F& f, int steps, uint64_t* t, uint64_t spacing_ns) {
    for (int done = 0; done < (steps < 0 ? -steps : steps); done += 8) {
      const int chunk = std::min(8, (steps < 0 ? -steps : steps) - done);
      step(steps < 0 ? -chunk : chunk, t, spacing_ns);
      f.latch(*t);
    }
  }
  void step(int steps, uint64_t* t, uint64_t spacing_ns) {
    for (int i = 0; i < (steps < 0 ? -steps : steps); ++i) {
      pos = (pos + (steps < 0 ? 3 : 1)) % 4;
      *t += spacing_ns;
      wire->set_level(a, (kQuadratureForward[pos] & 2) != 0, *t);
      wire->set_level(b, (kQuadratureForward[pos] & 1) != 0, *t);
    }
  }
};

struct Fixture {
  SimulatedGpio wire{16};
  std::unique_ptr<GpioSource> source;
  hal::InputHealth health;
  std::array<JointSample, 8> out{};

  Fixture() {
    const hal::InputLimits limits[4] = {};
    const int32_t initial[4] = {};
    health.init(limits, initial, 0);
  }
  explicit Fixture(const GpioSourceConfig& config) : Fixture() {
    std::string error;
    source = GpioSource::create(config, wire.chip(), &error);
    EXPECT_TRUE(source) << error;
  }
  size_t latch(uint64_t until) { return source->latch(until, out, health); }
};

GpioSourceConfig one_encoder(uint32_t cpt = 4096) {
  GpioSourceConfig c;
  c.name = "test-gpio";
  c.encoders.push_back(EncoderConfig{});
  c.encoders[0].input = 2;
  c.encoders[0].line_a = 0;
  c.encoders[0].line_b = 1;
  c.encoders[0].counts_per_turn = cpt;
  return c;
}

TEST(GpioSource, DecodesBothDirectionsIntoAngles) {
  Fixture f(one_encoder(4096));
  EncoderDriver enc{&f.wire, 0, 1};
  uint64_t t = 0;
  enc.run(f, 1024, &t, 10 * kUs);  // a quarter turn forward
  ASSERT_EQ(f.latch(t), 1u);
  EXPECT_EQ(f.out[0].input, 2);
  EXPECT_EQ(f.out[0].value, 1 << 30);
  EXPECT_EQ(f.out[0].timestamp_ns, t);
  EXPECT_EQ(f.source->state(), hal::SourceState::kOk);
  enc.run(f, -1536, &t, 10 * kUs);  // back 3/8 turn: to -1/8 turn
  ASSERT_EQ(f.latch(t), 1u);
  EXPECT_EQ(f.out[0].value, -(1 << 29));
  std::printf("forward 1024 then back 1536 counts (4096/turn): count %lld, angle %d (= -2^29), events %llu\n",
              static_cast<long long>(f.source->encoder(0).count()), f.out[0].value,
              static_cast<unsigned long long>(f.source->counters().events));
  EXPECT_EQ(f.source->encoder(0).count(), -512);
  EXPECT_EQ(f.source->encoder(0).counters().illegal, 0u);
}

TEST(GpioSource, InvertOffsetAndActiveLow) {
  GpioSourceConfig c = one_encoder(400);
  c.encoders[0].invert = true;
  c.encoders[0].offset = 1 << 30;
  c.encoders[0].active_low = true;
  SimulatedGpio wire(16);      // outlives the source
  Fixture g;                   // for its health object; the source runs on `wire`
  wire.set_level(0, true, 1);  // active low: physical 11 is the logical start state 00
  wire.set_level(1, true, 1);
  std::string error;
  g.source = GpioSource::create(c, wire.chip(), &error);
  ASSERT_TRUE(g.source) << error;
  uint64_t t = 10;
  // Logical forward = physical inverse of the Gray sequence.
  for (int i = 1; i <= 100; ++i) {
    const uint8_t ab = kQuadratureForward[i % 4];
    t += 1000;
    wire.set_level(0, (ab & 2) == 0, t);
    wire.set_level(1, (ab & 1) == 0, t);
    if (i % 8 == 0) g.source->latch(t, g.out, g.health);
  }
  ASSERT_EQ(g.latch(t), 1u);
  EXPECT_EQ(g.source->encoder(0).count(), 100);
  // 100 counts of 400 = quarter turn, inverted: -2^30, plus offset 2^30 = 0.
  EXPECT_EQ(g.out[0].value, 0);
}

TEST(GpioSource, EveryIllegalTransitionCountedAndDegraded) {
  Fixture f(one_encoder());
  uint64_t t = 1000;
  // 00 -> 11 -> 00, then 00 -> 10 (legal) -> 01 -> 10: every both-lines change.
  const uint8_t path[] = {3, 0, 2, 1, 2};
  const bool legal[] = {false, false, true, false, false};
  uint64_t illegal = 0;
  uint8_t prev = 0;
  for (size_t i = 0; i < sizeof path; ++i) {
    t += 1000;
    f.wire.set_level(0, (path[i] & 2) != 0, t);  // same kernel timestamp on both lines
    f.wire.set_level(1, (path[i] & 1) != 0, t);
    f.latch(t);
    illegal += legal[i] ? 0 : 1;
    EXPECT_EQ(f.source->encoder(0).counters().illegal, illegal) << int(prev) << "->" << int(path[i]);
    EXPECT_EQ(f.source->state(), legal[i] ? hal::SourceState::kOk : hal::SourceState::kDegraded);
    prev = path[i];
  }
  EXPECT_EQ(f.source->encoder(0).count(), 1);  // only 00 -> 10 moved it
  f.latch(t + 1000);
  EXPECT_EQ(f.source->state(), hal::SourceState::kOk);  // nothing new: healthy again
  std::printf("illegal transitions 00-11, 11-00, 01-10, 10-01: counted %llu; status: %s\n",
              static_cast<unsigned long long>(f.source->encoder(0).counters().illegal),
              f.source->status_line().c_str());
}

TEST(GpioSource, IndexHomingGatesSamples) {
  GpioSourceConfig c = one_encoder(4096);
  c.encoders[0].line_index = 2;
  c.encoders[0].index_count = 2048;  // the index sits at half a turn
  Fixture f(c);
  EncoderDriver enc{&f.wire, 0, 1};
  uint64_t t = 0;
  enc.step(300, &t, 10 * kUs);
  EXPECT_EQ(f.latch(t), 0u);  // not homed: nothing delivered, the input goes stale
  EXPECT_NE(f.source->status_line().find("not homed"), std::string::npos);
  t += 5 * kUs;
  f.wire.set_level(2, true, t);  // index pulse
  enc.step(4, &t, 10 * kUs);     // moves on while the index is high
  f.wire.set_level(2, false, t + 1);
  ASSERT_EQ(f.latch(t + 1), 1u);
  EXPECT_TRUE(f.source->encoder(0).homed());
  EXPECT_EQ(f.source->encoder(0).count(), 2052);
  EXPECT_EQ(static_cast<uint32_t>(f.out[0].value), (2052u << 20));
  std::printf("homed at the index: count %lld, angle 0x%08x\n", static_cast<long long>(f.source->encoder(0).count()),
              static_cast<uint32_t>(f.out[0].value));
}

TEST(GpioSource, LimitSwitchDebouncedIntoSampleFlags) {
  GpioSourceConfig c = one_encoder();
  c.limits.push_back(LimitSwitchConfig{});
  c.limits[0].input = 2;
  c.limits[0].line = 5;
  c.limits[0].side = LimitSide::kMax;
  c.limits[0].active_low = true;
  c.limits[0].debounce_ns = 2 * kMs;
  c.limits.push_back(LimitSwitchConfig{});
  c.limits[1].input = 3;  // a limit on an input without an encoder here
  c.limits[1].line = 6;
  c.limits[1].debounce_ns = 0;
  Fixture fx(c);
  // The lines start low: both switches (active low) pressed. Release both,
  // line 5 bouncing.
  uint64_t t = 1 * kMs;
  for (int i = 0; i < 6; ++i) fx.wire.set_level(5, i % 2 == 0, t + static_cast<uint64_t>(i) * 150 * kUs);
  fx.wire.set_level(5, true, t + 900 * kUs);
  fx.wire.set_level(6, true, t);
  ASSERT_EQ(fx.latch(t + 2 * kMs), 1u);
  // Line 5 was pressed (low) at creation; the release is not yet 2 ms old.
  EXPECT_EQ(fx.out[0].status, kSampleAtMaxLimit);
  EXPECT_TRUE(fx.source->limit_pressed(0));
  EXPECT_FALSE(fx.source->limit_pressed(1));
  ASSERT_EQ(fx.latch(t + 900 * kUs + 2 * kMs), 1u);
  EXPECT_EQ(fx.out[0].status, 0);
  EXPECT_FALSE(fx.source->limit_pressed(0));
  std::printf("limit: %llu bounces ignored, released at +%.3f ms (last edge +0.900 ms, debounce 2 ms)\n",
              static_cast<unsigned long long>(fx.source->limit(0).bounces()),
              static_cast<double>(fx.source->limit(0).changed_ns() - t) / 1e6);
  EXPECT_EQ(fx.source->limit(0).changes(), 1u);
  EXPECT_EQ(fx.source->limit(0).changed_ns(), t + 900 * kUs + 2 * kMs);
  // Press it for real.
  fx.wire.set_level(5, false, 20 * kMs);
  fx.latch(21 * kMs);
  EXPECT_EQ(fx.source->limit_flags(2), 0);
  fx.latch(22 * kMs);
  EXPECT_EQ(fx.source->limit_flags(2), kSampleAtMaxLimit);
  fx.wire.set_level(6, false, 22 * kMs);
  fx.latch(22 * kMs);
  EXPECT_EQ(fx.source->limit_flags(3), kSampleAtMinLimit);
}

TEST(GpioSource, EventsAfterTheTickWaitForTheNext) {
  Fixture f(one_encoder());
  EncoderDriver enc{&f.wire, 0, 1};
  uint64_t t = 0;
  enc.step(10, &t, kUs);  // edges at 1..10 us
  f.latch(5 * kUs);
  EXPECT_EQ(f.source->encoder(0).count(), 5);
  f.latch(10 * kUs);
  EXPECT_EQ(f.source->encoder(0).count(), 10);
}

TEST(GpioSource, KernelFifoOverflowShowsAsLostEdges) {
  Fixture f(one_encoder());
  EncoderDriver enc{&f.wire, 0, 1};
  uint64_t t = 0;
  enc.step(102, &t, kUs);  // 51 edges per line: the 16-event FIFOs overflow
  f.latch(t);
  const QuadratureCounters& c = f.source->encoder(0).counters();
  std::printf(
      "102 steps without a latch: %llu events dropped by the FIFOs, decoder saw %llu edges, %llu resyncs, "
      "%llu illegal, count %lld\n",
      static_cast<unsigned long long>(f.wire.dropped_events()), static_cast<unsigned long long>(c.edges),
      static_cast<unsigned long long>(c.resyncs), static_cast<unsigned long long>(c.illegal),
      static_cast<long long>(f.source->encoder(0).count()));
  EXPECT_EQ(f.wire.dropped_events(), 70u);
  EXPECT_EQ(c.resyncs, 1u);  // the read-back levels (11) disagree with the decoded state after 32 steps (00)
  EXPECT_EQ(f.source->counters().overflow_checks, 1u);
  EXPECT_EQ(f.source->encoder(0).count(), 32);
  EXPECT_EQ(f.source->state(), hal::SourceState::kDegraded);
}

TEST(GpioSource, SmallStagingBufferStillDrainsAllDueEvents) {
  GpioSourceConfig c = one_encoder();
  c.event_capacity = 16;
  Fixture f(c);
  EncoderDriver enc{&f.wire, 0, 1};
  uint64_t t = 0;
  enc.step(30, &t, kUs);  // 30 events, within the FIFOs (15 per line)
  f.latch(t);
  EXPECT_EQ(f.source->encoder(0).count(), 30);
}

TEST(GpioSource, ReadErrorIsDownThenRecovers) {
  Fixture f(one_encoder());
  f.wire.fail_reads(ENODEV);
  EXPECT_EQ(f.latch(1000), 0u);
  EXPECT_EQ(f.source->state(), hal::SourceState::kDown);
  EXPECT_EQ(f.source->counters().read_errors, 1u);
  f.wire.fail_reads(0);
  EXPECT_EQ(f.latch(2000), 1u);
  EXPECT_EQ(f.source->state(), hal::SourceState::kOk);
}

TEST(GpioSource, SyncEdgeStartsATick) {
  GpioSourceConfig c = one_encoder();
  c.sync.line = 7;
  Fixture f(c);
  SyncEdge e = f.source->wait_sync(0);
  EXPECT_EQ(e.result, WaitResult::kTimeout);
  f.wire.set_level(7, true, 123 * kUs);
  e = f.source->wait_sync(1 * kMs);
  EXPECT_EQ(e.result, WaitResult::kReady);
  EXPECT_EQ(e.timestamp_ns, 123 * kUs);
  EXPECT_EQ(e.missed, 0u);
  f.wire.set_level(7, false, 200 * kUs);  // a falling edge alone does not start a tick
  EXPECT_EQ(f.source->wait_sync(0).result, WaitResult::kTimeout);
  for (uint64_t k = 1; k <= 3; ++k) {  // three master ticks while we were busy
    f.wire.set_level(7, true, k * kMs);
    f.wire.set_level(7, false, k * kMs + 100 * kUs);
  }
  e = f.source->wait_sync(0);
  EXPECT_EQ(e.result, WaitResult::kReady);
  EXPECT_EQ(e.timestamp_ns, 3 * kMs);
  EXPECT_EQ(e.missed, 2u);
  std::printf("sync: %llu edges, %llu missed, %llu timeouts\n",
              static_cast<unsigned long long>(f.source->counters().sync_edges),
              static_cast<unsigned long long>(f.source->counters().sync_missed),
              static_cast<unsigned long long>(f.source->counters().sync_timeouts));
  EXPECT_EQ(f.source->counters().sync_timeouts, 2u);
}

// The sync trigger's view of the line: an active edge is an arrival from its
// timestamp on, until a tick latches at or after it; a falling edge is none.
TEST(GpioSource, SyncEdgeIsAnArrivalUntilATickLatchesIt) {
  GpioSourceConfig c = one_encoder();
  c.sync.line = 7;
  Fixture f(c);
  EXPECT_EQ(f.source->arrival_signals(), hal::kSignalsSync);
  EXPECT_FALSE(f.source->arrival(1 * kMs).sync);
  f.wire.set_level(7, true, 1500 * kUs);
  EXPECT_FALSE(f.source->arrival(1400 * kUs).sync) << "the edge is stamped after now";
  EXPECT_TRUE(f.source->arrival(1600 * kUs).sync);
  EXPECT_TRUE(f.source->arrival(1700 * kUs).sync) << "pending until a tick latches it";
  EXPECT_FALSE(f.source->arrival(1700 * kUs).complete) << "GPIO cannot tell a complete set";
  f.latch(1700 * kUs);
  EXPECT_FALSE(f.source->arrival(1800 * kUs).sync);
  f.wire.set_level(7, false, 1900 * kUs);
  EXPECT_FALSE(f.source->arrival(2 * kMs).sync) << "a falling edge starts no tick";
  EXPECT_EQ(f.source->counters().sync_edges, 1u);
  Fixture g(one_encoder());
  EXPECT_EQ(g.source->arrival_signals(), hal::kSignalsNothing);
  EXPECT_FALSE(g.source->arrival(1 * kMs).sync);
}

TEST(GpioSource, SyncActiveLowAndWithoutLine) {
  GpioSourceConfig c = one_encoder();
  c.sync.line = 7;
  c.sync.active_low = true;
  Fixture f(c);
  f.wire.set_level(7, true, 10);  // inactive edge for an active-low sync
  EXPECT_EQ(f.source->wait_sync(0).result, WaitResult::kTimeout);
  f.wire.set_level(7, false, 20);
  EXPECT_EQ(f.source->wait_sync(0).timestamp_ns, 20u);
  Fixture g(one_encoder());
  EXPECT_EQ(g.source->wait_sync(0).result, WaitResult::kError);
}

TEST(GpioSource, FaultLineAssertedUntilClearedAndOnExit) {
  for (bool active_low : {false, true}) {
    GpioSourceConfig c = one_encoder();
    c.fault.line = 9;
    c.fault.active_low = active_low;
    SimulatedGpio wire(16);
    std::string error;
    {
      auto source = GpioSource::create(c, wire.chip(), &error);
      ASSERT_TRUE(source) << error;
      EXPECT_EQ(wire.level(9), !active_low);  // asserted from the start
      EXPECT_TRUE(source->set_fault(false));
      EXPECT_EQ(wire.level(9), active_low);
      EXPECT_TRUE(source->set_fault(true));
      EXPECT_EQ(wire.level(9), !active_low);
      EXPECT_TRUE(source->set_fault(false));
    }
    EXPECT_EQ(wire.level(9), !active_low);  // released asserted
    EXPECT_FALSE(wire.requested(9));
  }
  Fixture f(one_encoder());
  EXPECT_FALSE(f.source->set_fault(true));
}

TEST(GpioSource, NoAllocationPerTick) {
  GpioSourceConfig c = one_encoder(4096);
  c.encoders[0].line_index = 2;
  c.limits.push_back(LimitSwitchConfig{});
  c.limits[0].input = 2;
  c.limits[0].line = 3;
  c.sync.line = 4;
  c.fault.line = 5;
  Fixture f(c);
  EncoderDriver enc{&f.wire, 0, 1};
  uint64_t t = 0;
  f.wire.set_level(2, true, ++t);
  f.wire.set_level(2, false, ++t);
  const int ticks = 5000;
  size_t samples = 0;
  test::AllocationCounter counter;
  for (int i = 0; i < ticks; ++i) {
    enc.step(i % 7 - 3, &t, kUs);
    if (i % 50 == 0) f.wire.set_level(3, (i / 50) % 2 == 0, t);
    f.wire.set_level(4, i % 2 == 0, t);
    f.source->wait_sync(0);
    samples += f.latch(t);
    f.source->set_fault(i % 100 == 0);
  }
  const uint64_t allocations = counter.allocations();
  std::printf("%d ticks, %zu samples, %llu events, %llu heap allocations\n", ticks, samples,
              static_cast<unsigned long long>(f.source->counters().events),
              static_cast<unsigned long long>(allocations));
  EXPECT_EQ(allocations, 0u);
  EXPECT_EQ(samples, static_cast<size_t>(ticks));
}

}  // namespace
}  // namespace sinew::hal::gpio
