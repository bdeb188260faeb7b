// The simulated twin behaves like the SocketCAN backend: queue order and
// limits, filters, error frames, bus-off, interface down with back-off.
#include "hal/can/simulated_can_bus.hpp"

#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "tests/support/alloc_guard.hpp"

namespace sinew::hal::can {
namespace {

CanFrame frame(uint32_t id, uint64_t t_ns, uint8_t tag = 0) {
  CanFrame f;
  f.id = id;
  f.len = 1;
  f.data[0] = tag;
  f.timestamp_ns = t_ns;
  return f;
}

TEST(SimulatedCanBus, DeliversInOrderAcrossPartialDrains) {
  SimulatedCanBus bus(16);
  EXPECT_EQ(bus.bus_state(), BusState::kErrorActive);
  for (uint8_t i = 0; i < 5; ++i) ASSERT_TRUE(bus.inject(frame(0x100, i, i)));
  std::array<CanFrame, 3> out;
  ASSERT_EQ(bus.drain(out, 0), 3u);
  EXPECT_EQ(out[0].data[0], 0);
  EXPECT_EQ(out[2].data[0], 2);
  EXPECT_EQ(bus.pending(), 2u);
  ASSERT_EQ(bus.drain(out, 0), 2u);
  EXPECT_EQ(out[0].data[0], 3);
  EXPECT_EQ(out[1].data[0], 4);
  EXPECT_EQ(bus.drain(out, 0), 0u);
  EXPECT_EQ(bus.counters().frames, 5u);
}

TEST(SimulatedCanBus, FullQueueDropsTheNewestAndCountsIt) {
  SimulatedCanBus bus(4);
  for (uint8_t i = 0; i < 6; ++i) bus.inject(frame(0x100, i, i));
  EXPECT_EQ(bus.counters().dropped, 2u);
  std::array<CanFrame, 8> out;
  ASSERT_EQ(bus.drain(out, 0), 4u);
  EXPECT_EQ(out[3].data[0], 3);
}

TEST(SimulatedCanBus, FiltersPassOnlyConfiguredIdentifiersAndAllErrors) {
  SimulatedCanBus bus(16);
  const FrameId ids[] = {{0x100, false}, {0x100, true}};
  ASSERT_TRUE(bus.set_filters(ids, nullptr));
  EXPECT_TRUE(bus.inject(frame(0x100, 0)));
  EXPECT_FALSE(bus.inject(frame(0x101, 0)));
  CanFrame ext = frame(0x100, 0);
  ext.extended = true;
  EXPECT_TRUE(bus.inject(ext));
  bus.controller_state(BusState::kErrorWarning, 1);
  std::array<CanFrame, 8> out;
  ASSERT_EQ(bus.drain(out, 0), 3u);
  EXPECT_EQ(out[2].kind, FrameKind::kError);
  EXPECT_EQ(bus.counters().dropped, 0u);  // filtered frames are not drops
}

TEST(SimulatedCanBus, ErrorFramesUpdateTheStateWhenDrained) {
  SimulatedCanBus bus(16);
  bus.controller_state(BusState::kErrorPassive, 5);
  EXPECT_EQ(bus.bus_state(), BusState::kErrorActive);  // not yet read, as with a socket
  std::array<CanFrame, 4> out;
  ASSERT_EQ(bus.drain(out, 10), 1u);
  EXPECT_EQ(bus.bus_state(), BusState::kErrorPassive);
  EXPECT_EQ(bus.counters().error_frames, 1u);
}

TEST(SimulatedCanBus, BusOffLosesFramesUntilRestartThenRecovers) {
  SimulatedCanBus bus(16);
  std::array<CanFrame, 8> out;
  bus.inject(frame(0x100, 1));
  bus.bus_off(2);
  EXPECT_FALSE(bus.inject(frame(0x100, 3)));  // off the bus: nothing received
  ASSERT_EQ(bus.drain(out, 4), 2u);
  EXPECT_EQ(bus.bus_state(), BusState::kBusOff);
  EXPECT_EQ(bus.counters().bus_off_events, 1u);

  bus.restart(5);
  EXPECT_TRUE(bus.inject(frame(0x100, 6)));
  ASSERT_EQ(bus.drain(out, 7), 2u);
  EXPECT_EQ(out[0].kind, FrameKind::kError);
  EXPECT_EQ(out[1].kind, FrameKind::kData);
  EXPECT_EQ(bus.bus_state(), BusState::kErrorActive);
  EXPECT_EQ(bus.counters().restarts, 1u);
  EXPECT_EQ(bus.counters().frames, 2u);
}

TEST(SimulatedCanBus, InterfaceDownIsReopenedWithBackoff) {
  const uint64_t ms = 1'000'000;
  SimulatedCanBus bus(16, {100 * ms, 400 * ms});
  std::array<CanFrame, 8> out;
  bus.inject(frame(0x100, 0));
  bus.set_interface_up(false);  // queued frame is lost with the interface
  EXPECT_FALSE(bus.inject(frame(0x100, 1)));

  EXPECT_EQ(bus.drain(out, 1000 * ms), 0u);  // ENETDOWN: closed, first retry at +100 ms
  EXPECT_EQ(bus.bus_state(), BusState::kInterfaceDown);
  EXPECT_EQ(bus.counters().interface_down_events, 1u);

  bus.drain(out, 1099 * ms);
  EXPECT_EQ(bus.counters().reopen_attempts, 0u);  // not due yet
  bus.drain(out, 1100 * ms);                      // attempt 1 fails: next at +200 ms
  EXPECT_EQ(bus.counters().reopen_attempts, 1u);
  bus.drain(out, 1299 * ms);
  EXPECT_EQ(bus.counters().reopen_attempts, 1u);
  bus.drain(out, 1300 * ms);  // attempt 2 fails: next at +400 ms (the cap)
  EXPECT_EQ(bus.counters().reopen_attempts, 2u);
  bus.drain(out, 1700 * ms);  // attempt 3 fails: next at +400 ms
  EXPECT_EQ(bus.counters().reopen_attempts, 3u);
  bus.drain(out, 2099 * ms);
  EXPECT_EQ(bus.counters().reopen_attempts, 3u);
  EXPECT_EQ(bus.bus_state(), BusState::kInterfaceDown);

  bus.set_interface_up(true);
  bus.drain(out, 2100 * ms);  // attempt 4 succeeds
  EXPECT_EQ(bus.counters().reopen_attempts, 4u);
  EXPECT_EQ(bus.counters().reopens, 1u);
  EXPECT_EQ(bus.bus_state(), BusState::kErrorActive);
  EXPECT_TRUE(bus.inject(frame(0x100, 2)));
  EXPECT_EQ(bus.drain(out, 2101 * ms), 1u);

  // The delay starts over after a success.
  bus.set_interface_up(false);
  bus.drain(out, 3000 * ms);
  bus.set_interface_up(true);
  bus.drain(out, 3100 * ms);
  EXPECT_EQ(bus.counters().reopens, 2u);
}

TEST(SimulatedCanBus, DrainDoesNotAllocate) {
  SimulatedCanBus bus(256);
  std::vector<CanFrame> out(64);
  test::AllocationCounter counter;
  for (int round = 0; round < 100; ++round) {
    for (uint8_t i = 0; i < 50; ++i) bus.inject(frame(0x100, static_cast<uint64_t>(round), i));
    if (round % 10 == 0) bus.controller_state(BusState::kErrorWarning, 0);
    bus.drain(out, static_cast<uint64_t>(round));
  }
  EXPECT_EQ(counter.allocations(), 0u);
}

}  // namespace
}  // namespace sinew::hal::can
