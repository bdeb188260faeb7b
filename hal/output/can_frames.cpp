#include "can_frames.hpp"

#include "le_bytes.hpp"

namespace sinew::hal::output {

namespace {
constexpr uint8_t kCanDataBytes = 8;
constexpr uint8_t kCounterMask = 0x0F;
}  // namespace

bool CanFrameEncoder::configure(const CanOutputOptions& options, std::string* error) {
  const uint32_t mask = options.extended_id ? CAN_EFF_MASK : CAN_SFF_MASK;
  if ((options.can_id & ~mask) != 0)
    return *error = "CAN identifier " + std::to_string(options.can_id) + " does not fit " +
                    (options.extended_id ? "29" : "11") + " bits",
           false;
  id_ = options.can_id | (options.extended_id ? CAN_EFF_FLAG : 0u);
  return true;
}

size_t CanFrameEncoder::encode(const PoseFrame& frame, std::span<can_frame> out) const {
  const uint32_t n = frame.input_count;
  if (n > out.size() || n > uint32_t{UINT16_MAX} + 1) return 0;
  if (n > 0 && (frame.input_value == nullptr || frame.input_status == nullptr)) return 0;
  // The counter follows the tick, so a tick whose frames never reached the bus shows as a jump.
  const auto counter = static_cast<uint8_t>(frame.tick & kCounterMask);
  for (uint32_t i = 0; i < n; ++i) {
    can_frame& f = out[i];
    f = can_frame{};
    f.can_id = id_;
    f.len = kCanDataBytes;
    store_u16(f.data, static_cast<uint16_t>(i));
    store_i32(f.data + 2, frame.input_value[i]);
    f.data[6] = frame.input_status[i];
    f.data[7] = counter;  // high nibble reserved (0)
  }
  return n;
}

bool decode_can_joint_frame(const can_frame& frame, CanJointFrame* out) {
  if (frame.len != kCanDataBytes || (frame.data[7] & ~kCounterMask) != 0) return false;
  out->input = load_u16(frame.data);
  out->value = load_i32(frame.data + 2);
  out->status = frame.data[6];
  out->counter = frame.data[7] & kCounterMask;
  return true;
}

}  // namespace sinew::hal::output
