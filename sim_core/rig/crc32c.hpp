// CRC-32C (Castagnoli, reflected polynomial 0x82F63B78), as in iSCSI and ext4.
#pragma once

#include <cstddef>
#include <cstdint>

namespace sinew::rig {

// Continues a CRC: pass 0 to start. crc32c("123456789") == 0xE3069283.
uint32_t crc32c(uint32_t crc, const uint8_t* data, size_t size);

}  // namespace sinew::rig
