// CRC-8 SAE J1850 against its published check values, and the E2E profile 1
// chaining against the AUTOSAR E2E protocol specification's profile 1 example.
#include <gtest/gtest.h>

#include <cstdint>
#include <vector>

#include "hal/can/crc8_sae_j1850.hpp"

namespace sinew::hal::can {
namespace {

std::vector<uint8_t> bytes(std::initializer_list<int> v) {
  std::vector<uint8_t> out;
  for (int b : v) out.push_back(static_cast<uint8_t>(b));
  return out;
}

TEST(Crc8SaeJ1850, CheckValueOf123456789) {
  const uint8_t ascii[] = {'1', '2', '3', '4', '5', '6', '7', '8', '9'};
  EXPECT_EQ(crc8_sae_j1850(ascii), 0x4B);
}

// The AUTOSAR CRC library specification's table for Crc_CalculateCRC8.
TEST(Crc8SaeJ1850, AutosarCrcLibraryCheckValues) {
  EXPECT_EQ(crc8_sae_j1850(bytes({0x00, 0x00, 0x00, 0x00})), 0x59);
  EXPECT_EQ(crc8_sae_j1850(bytes({0xF2, 0x01, 0x83})), 0x37);
  EXPECT_EQ(crc8_sae_j1850(bytes({0x0F, 0xAA, 0x00, 0x55})), 0x79);
  EXPECT_EQ(crc8_sae_j1850(bytes({0x00, 0xFF, 0x55, 0x11})), 0xB8);
  EXPECT_EQ(crc8_sae_j1850(bytes({0x33, 0x22, 0x55, 0xAA, 0xBB, 0xCC, 0xDD, 0xEE, 0xFF})), 0xCB);
  EXPECT_EQ(crc8_sae_j1850(bytes({0x92, 0x6B, 0x55})), 0x8C);
  EXPECT_EQ(crc8_sae_j1850(bytes({0xFF, 0xFF, 0xFF, 0xFF})), 0x74);
}

TEST(Crc8SaeJ1850, ChainedCallsEqualOneCall) {
  const auto all = bytes({0x33, 0x22, 0x55, 0xAA, 0xBB, 0xCC, 0xDD, 0xEE, 0xFF});
  const std::span<const uint8_t> s(all);
  const uint8_t first = crc8_sae_j1850(s.first(4));
  EXPECT_EQ(crc8_sae_j1850(s.subspan(4), first, false), crc8_sae_j1850(s));
}

// AUTOSAR E2E protocol specification, profile 1 example (data ID 0x123,
// DataIDMode BOTH, CRC in byte 0, counter in the low nibble of byte 1).
TEST(E2eProfile1Crc, SpecificationExample) {
  EXPECT_EQ(e2e_p01_crc(0x123, bytes({0, 0, 0, 0, 0, 0, 0})), 0xCC);  // counter 0
  EXPECT_EQ(e2e_p01_crc(0x123, bytes({1, 0, 0, 0, 0, 0, 0})), 0x91);  // counter 1
}

TEST(E2eProfile1Crc, EqualsPlainCrcWithZeroStartAndNoXorOverIdThenData) {
  // The profile's chaining makes it CRC-8 0x1D with register start 0x00 and
  // no final xor over [id low, id high, data...].
  const auto data = bytes({0x15, 0x78, 0x56, 0x34, 0x12, 0x00, 0x00});
  uint8_t reg = 0x00;
  for (uint8_t b : bytes({0x01, 0x53, 0x15, 0x78, 0x56, 0x34, 0x12, 0x00, 0x00})) {
    reg ^= b;
    for (int i = 0; i < 8; ++i) reg = static_cast<uint8_t>((reg & 0x80) != 0 ? (reg << 1) ^ 0x1D : reg << 1);
  }
  EXPECT_EQ(e2e_p01_crc(0x5301, data), reg);
}

TEST(E2eProfile1Crc, DataIdBytesMatterInOrder) {
  const auto data = bytes({1, 2, 3, 4, 5, 6, 7});
  EXPECT_NE(e2e_p01_crc(0x1234, data), e2e_p01_crc(0x3412, data));
  EXPECT_NE(e2e_p01_crc(0x1234, data), e2e_p01_crc(0x1235, data));
}

}  // namespace
}  // namespace sinew::hal::can
