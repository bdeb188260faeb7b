// The project's own CAN frame: one type for classic CAN, CAN FD, remote and
// error frames, independent of the kernel's structs so that decoders, logs
// and the simulated bus share it. Fixed size, no heap.
#pragma once

#include <array>
#include <cstdint>

namespace sinew::hal::can {

inline constexpr uint8_t kClassicMaxLen = 8;
inline constexpr uint8_t kFdMaxLen = 64;
inline constexpr uint32_t kStandardIdMask = 0x7FFu;       // 11-bit identifier
inline constexpr uint32_t kExtendedIdMask = 0x1FFFFFFFu;  // 29-bit identifier

enum class FrameKind : uint8_t {
  kData,
  kRemote,  // remote transmission request: no payload, `len` is the requested length
  kError,   // kernel error frame: `id` holds the error class bits, `data` the details
};

// CAN FD flags as carried in struct canfd_frame and in candump's "##<flags>".
enum FdFlags : uint8_t {
  kFdBitRateSwitch = 0x01,
  kFdErrorStateIndicator = 0x02,
  kFdFrameFormat = 0x04,
};

struct CanFrame {
  uint32_t id = 0;  // 11 or 29 bits (error frames: error class bits)
  FrameKind kind = FrameKind::kData;
  bool extended = false;      // 29-bit identifier
  bool fd = false;            // CAN FD frame
  uint8_t len = 0;            // payload length in bytes
  uint8_t fd_flags = 0;       // FdFlags, CAN FD only
  uint8_t len8_dlc = 0;       // classic CAN only: raw DLC 9..15 sent with 8 bytes, else 0
  uint64_t timestamp_ns = 0;  // reception time (see the source for its clock)
  std::array<uint8_t, kFdMaxLen> data{};
};

// CAN FD payload lengths are quantised: DLC 0..8 → 0..8, 9..15 → 12,16,20,24,32,48,64.
uint8_t fd_dlc_to_len(uint8_t dlc);
uint8_t fd_len_to_dlc(uint8_t len);  // smallest DLC whose length holds `len`
bool is_valid_fd_len(uint8_t len);   // one of the 16 lengths a DLC can express

// Structural validity: identifier fits its format, length fits its kind.
bool is_well_formed(const CanFrame& frame);

// Convenience constructors (tests, simulated rig).
CanFrame make_data_frame(uint32_t id, bool extended, const uint8_t* data, uint8_t len, bool fd = false);

}  // namespace sinew::hal::can
