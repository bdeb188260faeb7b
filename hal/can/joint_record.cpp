#include "joint_record.hpp"

#include "crc8_sae_j1850.hpp"

namespace sinew::hal::can {

void encode_joint_record(uint16_t data_id, const JointRecord& record, std::span<uint8_t, kJointRecordSize> out) {
  const auto v = static_cast<uint32_t>(record.value);
  out[1] = static_cast<uint8_t>((record.counter & 0x0Fu) | ((record.status & 0x0Fu) << 4));
  out[2] = static_cast<uint8_t>(v);
  out[3] = static_cast<uint8_t>(v >> 8);
  out[4] = static_cast<uint8_t>(v >> 16);
  out[5] = static_cast<uint8_t>(v >> 24);
  out[6] = 0;
  out[7] = 0;
  out[0] = e2e_p01_crc(data_id, out.subspan<1>());
}

RecordCheck decode_joint_record(uint16_t data_id, std::span<const uint8_t, kJointRecordSize> in, JointRecord& record) {
  if (e2e_p01_crc(data_id, in.subspan<1>()) != in[0]) return RecordCheck::kBadCrc;
  const uint8_t counter = in[1] & 0x0Fu;
  if (counter > kAliveCounterMax) return RecordCheck::kInvalidCounter;
  if (in[6] != 0 || in[7] != 0) return RecordCheck::kReservedNotZero;
  record.counter = counter;
  record.status = static_cast<uint8_t>(in[1] >> 4);
  const uint32_t v = static_cast<uint32_t>(in[2]) | (static_cast<uint32_t>(in[3]) << 8) |
                     (static_cast<uint32_t>(in[4]) << 16) | (static_cast<uint32_t>(in[5]) << 24);
  record.value = static_cast<int32_t>(v);  // two's complement reinterpretation (C++20)
  return RecordCheck::kOk;
}

uint8_t alive_counter_delta(uint8_t previous, uint8_t current) {
  return static_cast<uint8_t>((current + kAliveCounterModulo - previous) % kAliveCounterModulo);
}

}  // namespace sinew::hal::can
