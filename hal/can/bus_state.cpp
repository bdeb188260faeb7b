#include "bus_state.hpp"

#include <linux/can/error.h>

namespace sinew::hal::can {

const char* bus_state_name(BusState s) {
  switch (s) {
    case BusState::kErrorActive:
      return "error-active";
    case BusState::kErrorWarning:
      return "error-warning";
    case BusState::kErrorPassive:
      return "error-passive";
    case BusState::kBusOff:
      return "bus-off";
    case BusState::kInterfaceDown:
      return "interface-down";
  }
  return "unknown";
}

void BusStateTracker::enter(BusState s) {
  if (s == BusState::kBusOff && state_ != BusState::kBusOff) ++counters_.bus_off_events;
  if (s == BusState::kInterfaceDown && state_ != BusState::kInterfaceDown) ++counters_.interface_down_events;
  state_ = s;
}

void BusStateTracker::on_error_frame(const CanFrame& frame) {
  ++counters_.error_frames;
  const uint32_t cls = frame.id;
  const uint8_t* d = frame.data.data();
  if ((cls & (CAN_ERR_PROT | CAN_ERR_ACK | CAN_ERR_BUSERROR | CAN_ERR_LOSTARB | CAN_ERR_TRX | CAN_ERR_TX_TIMEOUT)) !=
      0) {
    ++counters_.bus_errors;
  }
#ifdef CAN_ERR_CNT
  if ((cls & CAN_ERR_CNT) != 0) {
    counters_.tx_error_counter = d[6];
    counters_.rx_error_counter = d[7];
  }
#endif
  if ((cls & CAN_ERR_CRTL) != 0) {
    if ((d[1] & (CAN_ERR_CRTL_RX_OVERFLOW | CAN_ERR_CRTL_TX_OVERFLOW)) != 0) ++counters_.controller_overflows;
    if (state_ != BusState::kBusOff) {
      if ((d[1] & (CAN_ERR_CRTL_RX_PASSIVE | CAN_ERR_CRTL_TX_PASSIVE)) != 0) {
        enter(BusState::kErrorPassive);
      } else if ((d[1] & (CAN_ERR_CRTL_RX_WARNING | CAN_ERR_CRTL_TX_WARNING)) != 0) {
        enter(BusState::kErrorWarning);
      }
    }
    if ((d[1] & CAN_ERR_CRTL_ACTIVE) != 0) enter(BusState::kErrorActive);
  }
  if ((cls & CAN_ERR_BUSOFF) != 0) enter(BusState::kBusOff);
  if ((cls & CAN_ERR_RESTARTED) != 0) {
    ++counters_.restarts;
    enter(BusState::kErrorActive);
  }
}

void BusStateTracker::on_frame_received() {
  ++counters_.frames;
  if (state_ == BusState::kBusOff) {
    ++counters_.restarts;
    enter(BusState::kErrorActive);
  }
}

void BusStateTracker::on_interface_down() { enter(BusState::kInterfaceDown); }

void BusStateTracker::on_interface_up() { enter(BusState::kErrorActive); }

namespace {
CanFrame error_frame(uint32_t cls, uint64_t timestamp_ns) {
  CanFrame f;
  f.kind = FrameKind::kError;
  f.id = cls;
  f.len = CAN_ERR_DLC;
  f.timestamp_ns = timestamp_ns;
  return f;
}
}  // namespace

CanFrame make_bus_off_error_frame(uint64_t timestamp_ns) { return error_frame(CAN_ERR_BUSOFF, timestamp_ns); }

CanFrame make_restarted_error_frame(uint64_t timestamp_ns) { return error_frame(CAN_ERR_RESTARTED, timestamp_ns); }

CanFrame make_controller_state_error_frame(BusState state, uint64_t timestamp_ns) {
  CanFrame f = error_frame(CAN_ERR_CRTL, timestamp_ns);
  switch (state) {
    case BusState::kErrorWarning:
      f.data[1] = CAN_ERR_CRTL_RX_WARNING | CAN_ERR_CRTL_TX_WARNING;
      break;
    case BusState::kErrorPassive:
      f.data[1] = CAN_ERR_CRTL_RX_PASSIVE | CAN_ERR_CRTL_TX_PASSIVE;
      break;
    default:
      f.data[1] = CAN_ERR_CRTL_ACTIVE;
      break;
  }
  return f;
}

CanFrame make_protocol_error_frame(uint64_t timestamp_ns) {
  CanFrame f = error_frame(CAN_ERR_PROT, timestamp_ns);
  f.data[2] = CAN_ERR_PROT_STUFF;
  return f;
}

}  // namespace sinew::hal::can
