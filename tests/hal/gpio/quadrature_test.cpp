// The decoder alone: the transition table, both directions, windows, index
// homing, and counts -> binary angle.
#include "hal/gpio/quadrature.hpp"

#include <gtest/gtest.h>

#include <cstdio>

namespace sinew::hal::gpio {
namespace {

// Forward Gray sequence of AB = (A << 1) | B.

TEST(QuadratureTable, EveryTransition) {
  int forward = 0, backward = 0, none = 0, illegal = 0;
  for (uint8_t from = 0; from < 4; ++from) {
    for (uint8_t to = 0; to < 4; ++to) {
      const int8_t s = quadrature_step(from, to);
      const int changed = __builtin_popcount(static_cast<unsigned>(from ^ to));
      std::printf("  %u%u -> %u%u : %s\n", from >> 1, from & 1u, to >> 1, to & 1u,
                  s == kIllegalStep ? "illegal"
                  : s == 1          ? "+1"
                  : s == -1         ? "-1"
                                    : "0");
      if (changed == 0) {
        EXPECT_EQ(s, 0);
      }
      if (changed == 2) {
        EXPECT_EQ(s, kIllegalStep);
      }
      forward += s == 1;
      backward += s == -1;
      none += s == 0;
      illegal += s == kIllegalStep;
    }
  }
  for (int i = 0; i < 4; ++i) {
    EXPECT_EQ(quadrature_step(kQuadratureForward[i], kQuadratureForward[(i + 1) % 4]), 1);
    EXPECT_EQ(quadrature_step(kQuadratureForward[(i + 1) % 4], kQuadratureForward[i]), -1);
  }
  std::printf("transition table: %d forward, %d backward, %d no change, %d illegal\n", forward, backward, none,
              illegal);
  EXPECT_EQ(forward, 4);
  EXPECT_EQ(backward, 4);
  EXPECT_EQ(none, 4);
  EXPECT_EQ(illegal, 4);
}

// Drives `steps` quarter periods forward (negative: backward) from state AB,
// one edge every 1000 ns starting at *t.
void drive(QuadratureDecoder& d, uint8_t& ab, int steps, uint64_t* t) {
  for (int i = 0; i < (steps < 0 ? -steps : steps); ++i) {
    int pos = 0;
    while (kQuadratureForward[pos] != ab) ++pos;
    const uint8_t next = kQuadratureForward[(pos + (steps < 0 ? 3 : 1)) % 4];
    const uint8_t diff = static_cast<uint8_t>(ab ^ next);
    *t += 1000;
    d.on_edge(diff == 2 ? 0 : 1, (next & diff) != 0, *t);
    ab = next;
  }
  d.settle(*t);
}

TEST(QuadratureDecoder, CountsBothDirections) {
  QuadratureDecoder d;
  d.reset(false, false, 0);
  uint8_t ab = 0;
  uint64_t t = 0;
  drive(d, ab, 400, &t);
  EXPECT_EQ(d.count(), 400);
  drive(d, ab, -1000, &t);
  EXPECT_EQ(d.count(), -600);
  drive(d, ab, 7, &t);
  std::printf("after +400, -1000, +7 quarter periods: count %lld, edges %llu, illegal %llu\n",
              static_cast<long long>(d.count()), static_cast<unsigned long long>(d.counters().edges),
              static_cast<unsigned long long>(d.counters().illegal));
  EXPECT_EQ(d.count(), -593);
  EXPECT_EQ(d.counters().illegal, 0u);
  EXPECT_EQ(d.counters().edges, 1407u);
}

TEST(QuadratureDecoder, EveryIllegalTransitionIsCountedAndResyncs) {
  for (uint8_t from = 0; from < 4; ++from) {
    QuadratureDecoder d;
    d.reset((from & 2) != 0, (from & 1) != 0, 0);
    const uint8_t to = static_cast<uint8_t>(from ^ 3u);
    d.on_edge(0, (to & 2) != 0, 5000);  // both edges with one kernel timestamp
    d.on_edge(1, (to & 1) != 0, 5000);
    d.settle(5000);
    EXPECT_EQ(d.counters().illegal, 1u) << int(from);
    EXPECT_EQ(d.count(), 0);
    EXPECT_EQ(d.state(), to);
    // The decoder counts normally from the observed state.
    int pos = 0;
    while (kQuadratureForward[pos] != to) ++pos;
    const uint8_t next = kQuadratureForward[(pos + 1) % 4];
    const uint8_t diff = static_cast<uint8_t>(to ^ next);
    d.on_edge(diff == 2 ? 0 : 1, (next & diff) != 0, 6000);
    d.settle(6000);
    EXPECT_EQ(d.count(), 1);
    std::printf("illegal %u%u -> %u%u counted; then +1 from there\n", from >> 1, from & 1u, to >> 1, to & 1u);
  }
}

TEST(QuadratureDecoder, WindowGroupsCloseEdges) {
  QuadratureDecoder d;
  d.reset(false, false, 1000);
  d.on_edge(0, true, 10'000);
  d.on_edge(1, true, 10'400);  // within the window: 00 -> 11 in one sample
  d.settle(11'000);
  EXPECT_EQ(d.counters().illegal, 1u);
  EXPECT_EQ(d.count(), 0);
  d.on_edge(0, false, 20'000);  // 11 -> 01: backward? no: forward order 0,2,3,1 -> 3 to 1 is +1
  d.on_edge(1, false, 22'000);  // after the window: a separate sample, 01 -> 00 (+1)
  d.settle(22'999);             // the second sample's window is still open
  EXPECT_EQ(d.count(), 1);
  d.settle(23'000);
  EXPECT_EQ(d.count(), 2);
  // A glitch (A up and down) inside one window changes nothing.
  d.on_edge(0, true, 30'000);
  d.on_edge(0, false, 30'100);
  d.settle(40'000);
  EXPECT_EQ(d.count(), 2);
  EXPECT_EQ(d.counters().illegal, 1u);
}

TEST(QuadratureDecoder, LostEdgeIsCounted) {
  QuadratureDecoder d;
  d.reset(false, false, 0);
  d.on_edge(0, true, 1000);
  d.on_edge(0, true, 2000);  // the falling edge between was lost
  d.settle(2000);
  EXPECT_EQ(d.counters().missed_edges, 1u);
  EXPECT_EQ(d.count(), 1);
}

TEST(QuadratureDecoder, IndexHoming) {
  QuadratureDecoder d;
  d.reset(false, false, 0);
  uint8_t ab = 0;
  uint64_t t = 0;
  drive(d, ab, 37, &t);
  EXPECT_FALSE(d.homed());
  d.on_index(t, 100, false);
  EXPECT_TRUE(d.homed());
  EXPECT_EQ(d.count(), 100);
  drive(d, ab, 10, &t);
  d.on_index(t, 100, false);  // only the first pulse homes
  EXPECT_EQ(d.count(), 110);
  d.on_index(t, 100, true);  // re-home on every pulse: a correction of 10 counts
  EXPECT_EQ(d.count(), 100);
  EXPECT_EQ(d.counters().index_pulses, 3u);
  EXPECT_EQ(d.counters().index_corrections, 1u);
}

TEST(CountsToAngle, TurnsAndRounding) {
  EXPECT_EQ(counts_to_angle(0, 4096, 0), 0);
  EXPECT_EQ(counts_to_angle(1024, 4096, 0), 1 << 30);             // quarter turn
  EXPECT_EQ(counts_to_angle(2048, 4096, 0), INT32_MIN);           // half turn
  EXPECT_EQ(counts_to_angle(-1024, 4096, 0), -(1 << 30));         // wraps below zero
  EXPECT_EQ(counts_to_angle(4096 * 5 + 1024, 4096, 0), 1 << 30);  // multi-turn wraps
  EXPECT_EQ(counts_to_angle(1024, 4096, 1 << 29), (1 << 30) + (1 << 29));
  // 1/3 turn of 2^32 = 1431655765.33 -> 1431655765; 2/3 = 2863311530.67 -> 2863311531
  EXPECT_EQ(counts_to_angle(1, 3, 0), 1431655765);
  EXPECT_EQ(static_cast<uint32_t>(counts_to_angle(2, 3, 0)), 2863311531u);
  // half-up: 1/2^30 turns * 2^32 = 4 exactly; 1/(2^30 - 1) rounds
  EXPECT_EQ(counts_to_angle(1, 1u << 30, 0), 4);
  EXPECT_EQ(counts_to_angle((1 << 30) - 1, 1u << 30, 0), -4);
  std::printf("1 count of 3/turn = %d, 1024 of 4096 = %d\n", counts_to_angle(1, 3, 0), counts_to_angle(1024, 4096, 0));
}

}  // namespace
}  // namespace sinew::hal::gpio
