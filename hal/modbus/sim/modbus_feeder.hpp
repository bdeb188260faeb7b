// The simulated rig's Modbus device: a ModbusServer whose holding registers
// hold the motion's value at the time each request arrives (the device
// measures on demand, on the server's thread), so what a client reads never
// lags the motion by more than its own request's latency, however busy the
// machine is. Input i is the signed
// 32-bit value at holding registers 2i, 2i+1 (high word first) in
// hundredths of a degree (rotations) or micrometres (translations), the
// layout `modbus_channels()` describes for the firmware's Modbus source. The
// plan's Modbus faults make the server mute or answer exceptions.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "hal/modbus/sim/modbus_server.hpp"
#include "hal/sim/fault_plan.hpp"
#include "hal/sim/rig_motion.hpp"

namespace sinew::hal::sim {

class ModbusFeeder {
 public:
  // rotation[i]: input i is an angle (else a length). The motion's and the
  // faults' time is the monotonic clock minus start_ns. Listens on
  // 127.0.0.1:port (0: any).
  bool start(RigMotion motion, std::vector<bool> rotation, FaultPlan faults, uint64_t start_ns, uint16_t port,
             std::string* error);
  void stop() { server_.stop(); }
  ~ModbusFeeder() { stop(); }
  uint16_t port() const { return server_.port(); }
  uint64_t requests() const { return server_.requests(); }

 private:
  void update(uint64_t now_ns);

  ModbusServer server_;
  RigMotion motion_{{}};
  std::vector<bool> rotation_;
  FaultPlan faults_;
  uint64_t start_ns_ = 0;
};

}  // namespace sinew::hal::sim
