// Groups the mapped channels into as few read requests as possible: channels
// of the same table whose registers are contiguous (or overlap, or are at
// most `max_gap` registers apart) share one request, up to the per-request
// register limit (125 by the protocol). Built once at start-up.
#pragma once

#include <cstdint>
#include <span>
#include <vector>

#include "register_channel.hpp"

namespace sinew::hal::modbus {

inline constexpr uint16_t kMaxReadRegisters = 125;  // protocol limit for functions 0x03 / 0x04

struct ReadRequest {
  RegisterTable table = RegisterTable::kHolding;
  uint16_t address = 0;            // first register read
  uint16_t count = 0;              // registers read
  std::vector<uint16_t> channels;  // indices into the channel list, by address
};

// max_registers: 1..125. max_gap: unmapped registers that may be read across
// to merge two requests (0: only contiguous ones; reading unmapped registers
// makes some devices answer "illegal data address").
std::vector<ReadRequest> plan_requests(std::span<const ChannelConfig> channels, uint16_t max_registers,
                                       uint16_t max_gap);

}  // namespace sinew::hal::modbus
