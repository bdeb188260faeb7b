#include "kernel_frame.hpp"

#include <cstring>

namespace sinew::hal::can {

bool from_kernel(const void* buffer, size_t bytes, uint64_t timestamp_ns, CanFrame& out) {
  out = CanFrame{};
  out.timestamp_ns = timestamp_ns;
  canid_t id = 0;
  if (bytes == CAN_MTU) {
    can_frame k;
    std::memcpy(&k, buffer, sizeof k);
    id = k.can_id;
    out.len = k.len > CAN_MAX_DLEN ? CAN_MAX_DLEN : k.len;
    if (out.len == CAN_MAX_DLEN && k.len8_dlc > CAN_MAX_DLC && k.len8_dlc <= CAN_MAX_RAW_DLC) out.len8_dlc = k.len8_dlc;
    std::memcpy(out.data.data(), k.data, out.len);
  } else if (bytes == CANFD_MTU) {
    canfd_frame k;
    std::memcpy(&k, buffer, sizeof k);
    id = k.can_id;
    out.fd = true;
    out.fd_flags = k.flags;
    out.len = k.len > CANFD_MAX_DLEN ? CANFD_MAX_DLEN : k.len;
    std::memcpy(out.data.data(), k.data, out.len);
  } else {
    return false;
  }
  if ((id & CAN_ERR_FLAG) != 0) {
    out.kind = FrameKind::kError;
    out.id = id & CAN_ERR_MASK;
    out.fd = false;
    return true;
  }
  out.extended = (id & CAN_EFF_FLAG) != 0;
  out.id = id & (out.extended ? CAN_EFF_MASK : CAN_SFF_MASK);
  if ((id & CAN_RTR_FLAG) != 0) out.kind = FrameKind::kRemote;
  return true;
}

size_t to_kernel(const CanFrame& frame, canfd_frame& out) {
  std::memset(&out, 0, sizeof out);
  if (!is_well_formed(frame)) return 0;
  canid_t id = frame.id;
  switch (frame.kind) {
    case FrameKind::kError:
      id |= CAN_ERR_FLAG;
      break;
    case FrameKind::kRemote:
      id |= CAN_RTR_FLAG;
      break;
    case FrameKind::kData:
      break;
  }
  if (frame.extended && frame.kind != FrameKind::kError) id |= CAN_EFF_FLAG;
  out.can_id = id;
  out.len = frame.len;
  if (frame.fd) {
    out.flags = frame.fd_flags;
    std::memcpy(out.data, frame.data.data(), frame.len);
    return CANFD_MTU;
  }
  can_frame k;
  std::memset(&k, 0, sizeof k);
  k.can_id = id;
  k.len = frame.len;
  k.len8_dlc = frame.len8_dlc;
  if (frame.kind != FrameKind::kRemote) std::memcpy(k.data, frame.data.data(), frame.len);
  std::memcpy(&out, &k, sizeof k);  // struct can_frame is the prefix of struct canfd_frame
  return CAN_MTU;
}

std::vector<can_filter> kernel_filters(std::span<const FrameId> ids) {
  std::vector<can_filter> filters;
  filters.reserve(ids.size());
  for (const FrameId& f : ids) {
    can_filter k;
    k.can_id = f.extended ? (f.id | CAN_EFF_FLAG) : f.id;
    k.can_mask = CAN_EFF_FLAG | (f.extended ? CAN_EFF_MASK : CAN_SFF_MASK);
    filters.push_back(k);
  }
  return filters;
}

}  // namespace sinew::hal::can
