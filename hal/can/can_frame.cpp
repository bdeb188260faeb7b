#include "can_frame.hpp"

#include <cstring>

namespace sinew::hal::can {

namespace {
constexpr uint8_t kFdLenOfDlc[16] = {0, 1, 2, 3, 4, 5, 6, 7, 8, 12, 16, 20, 24, 32, 48, 64};
}

uint8_t fd_dlc_to_len(uint8_t dlc) { return kFdLenOfDlc[dlc & 0x0Fu]; }

uint8_t fd_len_to_dlc(uint8_t len) {
  for (uint8_t dlc = 0; dlc < 16; ++dlc) {
    if (kFdLenOfDlc[dlc] >= len) return dlc;
  }
  return 15;
}

bool is_valid_fd_len(uint8_t len) { return len <= kFdMaxLen && fd_dlc_to_len(fd_len_to_dlc(len)) == len; }

bool is_well_formed(const CanFrame& frame) {
  const uint32_t id_mask = frame.extended ? kExtendedIdMask : kStandardIdMask;
  switch (frame.kind) {
    case FrameKind::kError:
      return !frame.fd && frame.len <= kClassicMaxLen && (frame.id & ~kExtendedIdMask) == 0;
    case FrameKind::kRemote:
      return !frame.fd && frame.len <= kClassicMaxLen && (frame.id & ~id_mask) == 0;
    case FrameKind::kData:
      break;
  }
  if ((frame.id & ~id_mask) != 0) return false;
  if (frame.fd) return is_valid_fd_len(frame.len) && frame.len8_dlc == 0;
  if (frame.len > kClassicMaxLen) return false;
  return frame.len8_dlc == 0 || (frame.len == kClassicMaxLen && frame.len8_dlc >= 9 && frame.len8_dlc <= 15);
}

CanFrame make_data_frame(uint32_t id, bool extended, const uint8_t* data, uint8_t len, bool fd) {
  CanFrame f;
  f.id = id;
  f.extended = extended;
  f.fd = fd;
  const uint8_t max = fd ? kFdMaxLen : kClassicMaxLen;
  f.len = len > max ? max : len;
  if (data != nullptr && f.len > 0) std::memcpy(f.data.data(), data, f.len);
  return f;
}

}  // namespace sinew::hal::can
