// [status] modbus_port: the daemon's health served as Modbus TCP registers
// (hal/modbus/status_server.hpp; layout in docs/modbus.md, "Status
// registers") for a PLC or HMI that polls the rig. After each tick the tick
// thread publishes the tick, its step time, the stale count, each input's
// status bits and each source's state: wait-free and allocation-free (the
// server's own thread answers the clients from a triple buffer).
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "config.hpp"
#include "firmware/runtime/runtime.hpp"
#include "hal/modbus/status_server.hpp"

namespace sinew::firmware {

class StatusPublisher {
 public:
  // Null with no error when [status] has no modbus_port; null with `error`
  // when the server cannot bind. Start-up only.
  static std::unique_ptr<StatusPublisher> create(const DaemonConfig& config, const Runtime& runtime,
                                                 std::string* error);

  // Tick thread, after Runtime::step: `frame` is what it returned.
  void publish(const Runtime& runtime, const hal::PoseFrame& frame, uint64_t step_ns);

  uint16_t port() const { return server_->port(); }
  std::string status_line() const;

 private:
  std::unique_ptr<hal::modbus::StatusServer> server_;
  std::vector<hal::SourceState> source_states_;  // sized at start: one per source
};

}  // namespace sinew::firmware
