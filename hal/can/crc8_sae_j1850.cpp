#include "crc8_sae_j1850.hpp"

#include <array>

namespace sinew::hal::can {

namespace {

constexpr uint8_t kPoly = 0x1D;
constexpr uint8_t kXor = 0xFF;

constexpr std::array<uint8_t, 256> make_table() {
  std::array<uint8_t, 256> t{};
  for (unsigned i = 0; i < 256; ++i) {
    unsigned r = i;
    for (int b = 0; b < 8; ++b) r = (r & 0x80u) != 0 ? ((r << 1) ^ kPoly) & 0xFFu : (r << 1) & 0xFFu;
    t[i] = static_cast<uint8_t>(r);
  }
  return t;
}

constexpr std::array<uint8_t, 256> kTable = make_table();

}  // namespace

uint8_t crc8_sae_j1850(std::span<const uint8_t> data, uint8_t start_value, bool first_call) {
  uint8_t reg = first_call ? kXor : static_cast<uint8_t>(start_value ^ kXor);
  for (uint8_t byte : data) reg = kTable[static_cast<uint8_t>(reg ^ byte)];
  return static_cast<uint8_t>(reg ^ kXor);
}

uint8_t e2e_p01_crc(uint16_t data_id, std::span<const uint8_t> payload_after_crc) {
  // AUTOSAR E2E profile 1 (SWS E2E library): start value 0xFF with
  // IsFirstCall = FALSE for the data ID, chained through the data, and the
  // library's final xor undone at the end. The published profile 1 examples
  // (data ID 0x123, zero payload: 0xCC, counter 1: 0x91) depend on this.
  const uint8_t id_bytes[2] = {static_cast<uint8_t>(data_id & 0xFFu), static_cast<uint8_t>(data_id >> 8)};
  uint8_t crc = crc8_sae_j1850(id_bytes, kXor, false);
  crc = crc8_sae_j1850(payload_after_crc, crc, false);
  return static_cast<uint8_t>(crc ^ kXor);
}

}  // namespace sinew::hal::can
