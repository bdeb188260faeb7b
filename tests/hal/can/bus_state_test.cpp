// Error frames → bus state, as the kernel's CAN drivers report them.
#include "hal/can/bus_state.hpp"

#include <gtest/gtest.h>
#include <linux/can/error.h>

namespace sinew::hal::can {
namespace {

BusStateTracker active_tracker() {
  BusStateTracker t;
  t.on_interface_up();
  return t;
}

TEST(BusState, StartsDownUntilOpened) {
  BusStateTracker t;
  EXPECT_EQ(t.state(), BusState::kInterfaceDown);
  t.on_interface_up();
  EXPECT_EQ(t.state(), BusState::kErrorActive);
}

TEST(BusState, ControllerWarningAndPassive) {
  BusStateTracker t = active_tracker();
  t.on_error_frame(make_controller_state_error_frame(BusState::kErrorWarning, 0));
  EXPECT_EQ(t.state(), BusState::kErrorWarning);
  t.on_error_frame(make_controller_state_error_frame(BusState::kErrorPassive, 0));
  EXPECT_EQ(t.state(), BusState::kErrorPassive);
  t.on_error_frame(make_controller_state_error_frame(BusState::kErrorActive, 0));
  EXPECT_EQ(t.state(), BusState::kErrorActive);
  EXPECT_EQ(t.counters().error_frames, 3u);
  EXPECT_EQ(t.counters().bus_off_events, 0u);
}

TEST(BusState, BusOffAndRestart) {
  BusStateTracker t = active_tracker();
  t.on_error_frame(make_bus_off_error_frame(0));
  EXPECT_EQ(t.state(), BusState::kBusOff);
  EXPECT_EQ(t.counters().bus_off_events, 1u);
  // Controller-problem frames do not end bus-off; only a restart does.
  t.on_error_frame(make_controller_state_error_frame(BusState::kErrorPassive, 0));
  EXPECT_EQ(t.state(), BusState::kBusOff);
  t.on_error_frame(make_bus_off_error_frame(0));  // repeated report: one event
  EXPECT_EQ(t.counters().bus_off_events, 1u);
  t.on_error_frame(make_restarted_error_frame(0));
  EXPECT_EQ(t.state(), BusState::kErrorActive);
  EXPECT_EQ(t.counters().restarts, 1u);
}

TEST(BusState, AReceivedFrameEndsBusOffWhoseRestartWasMissed) {
  BusStateTracker t = active_tracker();
  t.on_error_frame(make_bus_off_error_frame(0));
  t.on_frame_received();
  EXPECT_EQ(t.state(), BusState::kErrorActive);
  EXPECT_EQ(t.counters().restarts, 1u);
  EXPECT_EQ(t.counters().frames, 1u);
}

TEST(BusState, ProtocolErrorsAreCountedWithoutChangingState) {
  BusStateTracker t = active_tracker();
  t.on_error_frame(make_protocol_error_frame(0));
  CanFrame ack;
  ack.kind = FrameKind::kError;
  ack.id = CAN_ERR_ACK;
  t.on_error_frame(ack);
  EXPECT_EQ(t.state(), BusState::kErrorActive);
  EXPECT_EQ(t.counters().bus_errors, 2u);
}

TEST(BusState, OverflowAndErrorCounters) {
  BusStateTracker t = active_tracker();
  CanFrame f;
  f.kind = FrameKind::kError;
  f.id = CAN_ERR_CRTL | CAN_ERR_CNT;
  f.data[1] = CAN_ERR_CRTL_RX_OVERFLOW;
  f.data[6] = 97;
  f.data[7] = 12;
  t.on_error_frame(f);
  EXPECT_EQ(t.counters().controller_overflows, 1u);
  EXPECT_EQ(t.counters().tx_error_counter, 97);
  EXPECT_EQ(t.counters().rx_error_counter, 12);
  EXPECT_EQ(t.state(), BusState::kErrorActive);  // overflow alone is no state change
}

TEST(BusState, InterfaceDownIsCountedOncePerTransition) {
  BusStateTracker t = active_tracker();
  t.on_interface_down();
  t.on_interface_down();
  EXPECT_EQ(t.state(), BusState::kInterfaceDown);
  EXPECT_EQ(t.counters().interface_down_events, 1u);
  EXPECT_STREQ(bus_state_name(t.state()), "interface-down");
}

}  // namespace
}  // namespace sinew::hal::can
