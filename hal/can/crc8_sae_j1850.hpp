// CRC-8 SAE J1850 (polynomial 0x1D), with the AUTOSAR CRC library's calling
// convention so that E2E profile 1 can chain it exactly as AUTOSAR does:
//   first call:  register starts at 0xFF;
//   later calls: register starts at start_value ^ 0xFF (undoing the previous xor-out);
//   result:      register ^ 0xFF.
// Check value: crc8_sae_j1850("123456789") == 0x4B.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace sinew::hal::can {

uint8_t crc8_sae_j1850(std::span<const uint8_t> data, uint8_t start_value = 0xFF, bool first_call = true);

// AUTOSAR E2E profile 1 CRC, data ID mode "both" (low byte, then high byte),
// over the data bytes that follow the CRC byte. Equivalent to CRC-8 0x1D with
// register start 0x00 and no final xor over [id_lo, id_hi, payload...].
uint8_t e2e_p01_crc(uint16_t data_id, std::span<const uint8_t> payload_after_crc);

}  // namespace sinew::hal::can
