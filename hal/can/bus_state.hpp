// CAN bus state as the kernel reports it through error frames
// (linux/can/error.h), shared by the SocketCAN backend and its simulated twin
// so both interpret the same frames the same way.
#pragma once

#include <cstdint>

#include "can_frame.hpp"

namespace sinew::hal::can {

enum class BusState : uint8_t {
  kErrorActive,    // normal operation
  kErrorWarning,   // an error counter reached 96: still communicating
  kErrorPassive,   // an error counter reached 128: communicating, no active error flags
  kBusOff,         // transmit error counter passed 255: controller off the bus until restarted
  kInterfaceDown,  // interface down / missing (ENETDOWN, ENODEV) or socket not open: being reopened
};

const char* bus_state_name(BusState s);

struct BusCounters {
  uint64_t frames = 0;                // data and remote frames delivered
  uint64_t error_frames = 0;          // error frames received
  uint64_t bus_errors = 0;            // error frames reporting protocol, ACK, arbitration or transceiver errors
  uint64_t bus_off_events = 0;        // transitions into bus-off
  uint64_t restarts = 0;              // controller restarts reported after bus-off
  uint64_t controller_overflows = 0;  // controller RX/TX buffer overflows reported by error frames
  uint64_t dropped = 0;               // frames lost before delivery (socket queue full, SO_RXQ_OVFL)
  // Frames with identifiers the decoder does not read (another device's),
  // filtered out in software (candump replay, the simulated bus). SocketCAN's
  // kernel filter drops them unseen, so there they are not counted.
  uint64_t foreign_frames = 0;
  uint64_t read_errors = 0;  // failed or truncated reads
  uint64_t interface_down_events = 0;
  uint64_t reopen_attempts = 0;
  uint64_t reopens = 0;          // successful reopens after being down
  uint8_t tx_error_counter = 0;  // last TEC/REC reported (CAN_ERR_CNT), if the driver reports them
  uint8_t rx_error_counter = 0;
};

class BusStateTracker {
 public:
  // Interprets one kernel error frame (id = error class bits, data[] details).
  void on_error_frame(const CanFrame& frame);
  // A data or remote frame was received: the controller is on the bus, so
  // bus-off (whose restart message may have been lost) is over.
  void on_frame_received();
  void on_interface_down();
  void on_interface_up();

  BusState state() const { return state_; }
  BusCounters& counters() { return counters_; }
  const BusCounters& counters() const { return counters_; }

 private:
  void enter(BusState s);

  BusState state_ = BusState::kInterfaceDown;
  BusCounters counters_;
};

// Error frames as a driver would send them (simulated bus, tests).
CanFrame make_bus_off_error_frame(uint64_t timestamp_ns);
CanFrame make_restarted_error_frame(uint64_t timestamp_ns);
// kErrorActive, kErrorWarning or kErrorPassive, as a controller-problem frame.
CanFrame make_controller_state_error_frame(BusState state, uint64_t timestamp_ns);
CanFrame make_protocol_error_frame(uint64_t timestamp_ns);

}  // namespace sinew::hal::can
