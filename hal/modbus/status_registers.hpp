// The status server's register image (docs/modbus.md has the table): a fixed
// header, one register per input source, one per rig input. The same image is
// served as holding registers and as input registers, from address 0.
// 32- and 64-bit values are high word first.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "hal/common/input_source.hpp"

namespace sinew::hal::modbus {

namespace status_reg {
inline constexpr uint16_t kLayoutVersion = 0;  // = kLayout
inline constexpr uint16_t kHeartbeat = 1;      // +1 per publish, wraps
inline constexpr uint16_t kTick = 2;           // 4 registers, u64
inline constexpr uint16_t kLastStepUs = 6;     // 2 registers, u32, saturated
inline constexpr uint16_t kStaleCount = 8;     // inputs currently stale
inline constexpr uint16_t kInputCount = 9;
inline constexpr uint16_t kSourceCount = 10;
inline constexpr uint16_t kSourcesDown = 11;
inline constexpr uint16_t kSourcesDegraded = 12;
inline constexpr uint16_t kSourceState = 16;  // kMaxSources registers: 0 ok, 1 degraded, 2 down
inline constexpr uint16_t kInputStatus = 32;  // one per rig input: JointStatus bits
}  // namespace status_reg

inline constexpr uint16_t kStatusLayout = 1;
inline constexpr size_t kMaxStatusSources = 16;
inline constexpr size_t kMaxStatusInputs = 65536 - status_reg::kInputStatus;

// What the tick publishes. Spans are read during publish() only.
struct StatusUpdate {
  uint64_t tick = 0;
  uint64_t last_step_ns = 0;
  uint32_t stale_count = 0;
  std::span<const uint8_t> input_status;  // JointStatus bits per rig input
  std::span<const SourceState> source_states;
};

// Registers needed for `inputs` rig inputs.
inline constexpr size_t status_register_count(size_t inputs) { return status_reg::kInputStatus + inputs; }

// Writes the whole image (`image.size()` = status_register_count(inputs));
// inputs or sources beyond the image's room are left out. No allocation.
void encode_status(const StatusUpdate& update, uint16_t heartbeat, std::span<uint16_t> image);

uint16_t source_state_code(SourceState s);

}  // namespace sinew::hal::modbus
