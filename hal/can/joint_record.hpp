// One joint's 8-byte record of the default joint-stream protocol
// (docs/can-protocol.md): the whole payload of a classic frame, or one of up
// to eight slots of a packed CAN FD frame.
//
//   byte 0     CRC-8 (AUTOSAR E2E profile 1 over data ID + bytes 1..7)
//   byte 1     bits 0..3 alive counter 0..14, bits 4..7 status
//   bytes 2..5 value, int32 little-endian (signed binary angle: 2^32 = one turn)
//   bytes 6..7 reserved, zero
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace sinew::hal::can {

inline constexpr size_t kJointRecordSize = 8;
inline constexpr uint8_t kAliveCounterMax = 14;  // counts 0..14; 15 is invalid
inline constexpr uint8_t kAliveCounterModulo = 15;

struct JointRecord {
  uint8_t counter = 0;  // 0..14
  uint8_t status = 0;   // 4 bits (SampleStatus)
  int32_t value = 0;
};

enum class RecordCheck : uint8_t {
  kOk,
  kBadCrc,
  kInvalidCounter,   // counter nibble 15
  kReservedNotZero,  // bytes 6..7 not zero
};

// Writes the 8 bytes, CRC included. counter and status are masked to 4 bits.
void encode_joint_record(uint16_t data_id, const JointRecord& record, std::span<uint8_t, kJointRecordSize> out);

// Checks CRC first (nothing else is trusted without it), then the counter
// nibble and reserved bytes; fills `record` only when the result is kOk.
RecordCheck decode_joint_record(uint16_t data_id, std::span<const uint8_t, kJointRecordSize> in, JointRecord& record);

// Alive-counter distance from `previous` to `current` modulo 15 (14 → 0 is 1).
uint8_t alive_counter_delta(uint8_t previous, uint8_t current);

}  // namespace sinew::hal::can
