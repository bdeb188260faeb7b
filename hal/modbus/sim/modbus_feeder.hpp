// The simulated rig's Modbus device: a ModbusServer whose holding registers
// follow the motion in real time, on its own thread. Input i is the signed
// 32-bit value at holding registers 2i, 2i+1 (high word first) in
// hundredths of a degree (rotations) or micrometres (translations), the
// layout `modbus_channels()` describes for the firmware's Modbus source. The
// plan's Modbus faults make the server mute or answer exceptions.
#pragma once

#include <atomic>
#include <cstdint>
#include <string>
#include <thread>
#include <vector>

#include "hal/modbus/sim/modbus_server.hpp"
#include "hal/sim/fault_plan.hpp"
#include "hal/sim/rig_motion.hpp"

namespace sinew::hal::sim {

class ModbusFeeder {
 public:
  // rotation[i]: input i is an angle (else a length). update_period_ns: how
  // often the registers are refreshed. Listens on 127.0.0.1:port (0: any).
  bool start(RigMotion motion, std::vector<bool> rotation, FaultPlan faults, uint64_t start_ns,
             uint64_t update_period_ns, uint16_t port, std::string* error);
  void stop();
  ~ModbusFeeder() { stop(); }
  uint16_t port() const { return server_.port(); }
  uint64_t requests() const { return server_.requests(); }

 private:
  void run();
  void update(uint64_t now_ns);

  ModbusServer server_;
  RigMotion motion_{{}};
  std::vector<bool> rotation_;
  FaultPlan faults_;
  uint64_t start_ns_ = 0;
  uint64_t period_ns_ = 0;
  std::atomic<bool> stopping_{false};
  std::thread thread_;
};

}  // namespace sinew::hal::sim
