// Conversions between the kernel's SocketCAN structs (linux/can.h) and
// CanFrame, and the CAN_RAW_FILTER entries for a set of identifiers. Pure
// functions: testable without a CAN interface.
#pragma once

#include <linux/can.h>

#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "can_frame.hpp"
#include "frame_decoder.hpp"

namespace sinew::hal::can {

// `bytes` is what read/recvmsg returned: CAN_MTU (struct can_frame) or
// CANFD_MTU (struct canfd_frame). Returns false for any other size.
bool from_kernel(const void* buffer, size_t bytes, uint64_t timestamp_ns, CanFrame& out);

// Fills `out` and returns the number of bytes to write (CAN_MTU or
// CANFD_MTU), or 0 for a frame that is not well formed.
size_t to_kernel(const CanFrame& frame, canfd_frame& out);

// One exact-match filter per identifier (11-bit and 29-bit kept apart by
// CAN_EFF_FLAG in the mask). Remote frames pass so that they can be counted.
std::vector<can_filter> kernel_filters(std::span<const FrameId> ids);

}  // namespace sinew::hal::can
