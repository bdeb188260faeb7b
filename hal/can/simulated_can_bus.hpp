// In-process twin of the SocketCAN backend: a fixed ring buffer standing for
// the socket's receive queue, kernel-style identifier filters, error frames
// interpreted by the same BusStateTracker, interface down/up with the same
// reopen back-off. Tests and the simulated rig inject; receivers drain.
#pragma once

#include <cstddef>
#include <string>
#include <vector>

#include "frame_source.hpp"
#include "reopen_backoff.hpp"

namespace sinew::hal::can {

class SimulatedCanBus final : public FrameSource {
 public:
  // capacity: frames the receive queue holds (like SO_RCVBUF); allocated here.
  explicit SimulatedCanBus(size_t capacity = 1024, BackoffPolicy backoff = {});

  const char* name() const override { return "simulated-can"; }
  bool set_filters(std::span<const FrameId> ids, std::string* error) override;
  size_t drain(std::span<CanFrame> out, uint64_t now_ns) override;
  BusState bus_state() const override { return tracker_.state(); }
  const BusCounters& counters() const override { return tracker_.counters(); }

  // --- the bus side (what the wire and the driver would do) ---
  // Queues a frame as received at frame.timestamp_ns. Returns false when it
  // does not reach the queue: filtered out, controller bus-off, interface
  // down, or queue full (counted as dropped, like SO_RXQ_OVFL).
  bool inject(const CanFrame& frame);
  // The controller goes bus-off: a bus-off error frame is queued and data
  // frames are lost until restart().
  void bus_off(uint64_t timestamp_ns);
  // The driver restarts the controller (restart-ms): queues CAN_ERR_RESTARTED.
  void restart(uint64_t timestamp_ns);
  // Error-warning / error-passive / back to error-active, as a controller frame.
  void controller_state(BusState state, uint64_t timestamp_ns);
  // Interface administratively down (ENETDOWN on the next drain, queue lost)
  // or up again (the next due reopen attempt succeeds).
  void set_interface_up(bool up);

  size_t pending() const { return count_; }

 private:
  bool push(const CanFrame& frame);
  bool passes_filter(const CanFrame& frame) const;

  std::vector<CanFrame> ring_;
  size_t head_ = 0;
  size_t count_ = 0;
  std::vector<FrameId> filters_;
  BusStateTracker tracker_;
  ReopenBackoff backoff_;
  bool interface_up_ = true;
  bool open_ = true;            // the "socket"; closed after the interface went down
  bool down_reported_ = false;  // ENETDOWN pending for the next drain
  bool controller_bus_off_ = false;
};

}  // namespace sinew::hal::can
