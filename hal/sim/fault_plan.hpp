// Faults the simulated rig injects, each over a time window of the run:
// what a real bus, encoder or PLC link does wrong. The firmware's documented
// reaction to each is tested end to end (tests/integration).
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace sinew::hal::sim {

enum class FaultKind : uint8_t {
  kDrop,             // CAN frames not sent (inputs go stale after their timeout)
  kDelay,            // CAN frames arrive `amount` ns late
  kDuplicate,        // every CAN frame sent twice (the copy repeats the alive counter)
  kCorrupt,          // one payload bit flipped (bad CRC)
  kStuckCounter,     // the alive counter stops advancing (repeated counter)
  kOutOfRange,       // the value sent is far beyond the joint's range
  kBusOff,           // the controller goes bus-off at the start, restarts at the end
  kModbusTimeout,    // the Modbus server stops answering
  kModbusException,  // the Modbus server answers exception 4 (server device failure)
  kEncoderGlitch,    // both quadrature lines of an encoder spike together (illegal transitions)
};

struct Fault {
  FaultKind kind = FaultKind::kDrop;
  uint64_t from_ns = 0;  // window [from, to) relative to the run's start
  uint64_t to_ns = 0;
  int32_t input = -1;   // the input whose frames are affected; -1: all
  uint64_t amount = 0;  // kDelay: nanoseconds
};

struct FaultPlan {
  std::vector<Fault> faults;
  // The first fault of `kind` active at t for `input` (or for all), or null.
  const Fault* active(FaultKind kind, uint64_t t_ns, int32_t input) const;
};

const char* fault_kind_name(FaultKind kind);
// "drop", "delay", ... (the names used in configs); false if unknown.
bool parse_fault_kind(const std::string& name, FaultKind* kind);

}  // namespace sinew::hal::sim
