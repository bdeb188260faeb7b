#include "hal/common/input_health.hpp"

#include <gtest/gtest.h>

#include "tests/support/alloc_guard.hpp"
#include "tests/support/time_units.hpp"

using sinew::hal::InputHealth;
using sinew::hal::InputLimits;
namespace hal = sinew::hal;

namespace {
using sinew::test::kMs;
InputHealth make(uint64_t timeout_ns) {
  InputHealth h;
  const InputLimits limits[2] = {{-1000, 1000, timeout_ns}, {-1000, 1000, timeout_ns}};
  const int32_t initial[2] = {0, 0};
  h.init(limits, initial, 0);
  return h;
}
}  // namespace

TEST(InputHealth, AcceptsInRangeSamples) {
  InputHealth h = make(15 * kMs);
  const hal::JointSample s[] = {{0, 500, 1 * kMs, 0}, {1, -200, 1 * kMs, 0}};
  h.begin_tick();
  h.apply(s);
  h.end_tick(2 * kMs);
  EXPECT_EQ(h.values()[0], 500);
  EXPECT_EQ(h.values()[1], -200);
  EXPECT_EQ(h.status()[0], hal::kJointOk);
  EXPECT_EQ(h.counters(0).accepted, 1u);
}

TEST(InputHealth, OutOfRangeIsRejectedCountedAndHolds) {
  InputHealth h = make(15 * kMs);
  const hal::JointSample good[] = {{0, 500, 1 * kMs, 0}};
  const hal::JointSample bad[] = {{0, 5000, 2 * kMs, 0}, {0, 10, 2 * kMs, hal::kSampleSenderFault}};
  h.begin_tick();
  h.apply(good);
  h.end_tick(1 * kMs);
  h.begin_tick();
  h.apply(bad);
  h.end_tick(2 * kMs);
  EXPECT_EQ(h.values()[0], 500);  // last good value held
  EXPECT_TRUE(h.status()[0] & hal::kJointRejected);
  EXPECT_EQ(h.counters(0).rejected[static_cast<int>(hal::RejectReason::kOutOfRange)], 2u);
  h.begin_tick();  // the rejection flag lasts one tick
  h.end_tick(3 * kMs);
  EXPECT_FALSE(h.status()[0] & hal::kJointRejected);
}

TEST(InputHealth, StaleAfterTimeoutThenRecovers) {
  InputHealth h = make(15 * kMs);
  const hal::JointSample s0[] = {{0, 100, 10 * kMs, 0}};
  h.begin_tick();
  h.apply(s0);
  h.end_tick(10 * kMs);
  h.begin_tick();
  h.end_tick(25 * kMs);  // exactly the timeout: not yet stale
  EXPECT_FALSE(h.status()[0] & hal::kJointStale);
  h.begin_tick();
  h.end_tick(26 * kMs);
  EXPECT_TRUE(h.status()[0] & hal::kJointStale);
  EXPECT_EQ(h.values()[0], 100);
  EXPECT_EQ(h.counters(0).stale_events, 1u);
  EXPECT_EQ(h.stale_count(), 2u);  // input 1 never sent anything
  const hal::JointSample s1[] = {{0, 120, 27 * kMs, 0}};
  h.begin_tick();
  h.apply(s1);
  h.end_tick(27 * kMs);
  EXPECT_FALSE(h.status()[0] & hal::kJointStale);
  EXPECT_EQ(h.values()[0], 120);
}

TEST(InputHealth, UnknownInputsAreCountedAndPerTickWorkDoesNotAllocate) {
  InputHealth h = make(0);
  const hal::JointSample s[] = {{7, 1, 1, 0}};
  sinew::test::AllocationCounter allocations;
  for (int i = 0; i < 1000; ++i) {
    h.begin_tick();
    h.apply(s);
    h.reject(0, hal::RejectReason::kBadCrc);
    h.end_tick(static_cast<uint64_t>(i));
  }
  EXPECT_EQ(allocations.allocations(), 0u);
  EXPECT_EQ(h.unassigned().rejected[static_cast<int>(hal::RejectReason::kUnknownId)], 1000u);
  EXPECT_EQ(h.counters(0).rejected[static_cast<int>(hal::RejectReason::kBadCrc)], 1000u);
}
