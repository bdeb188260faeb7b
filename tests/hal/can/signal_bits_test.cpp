// DBC bit placement, against frames computed by hand.
#include "hal/can/signal_bits.hpp"

#include <gtest/gtest.h>

#include <array>
#include <cstdint>

namespace sinew::hal::can {
namespace {

using Payload = std::array<uint8_t, 64>;

Payload payload(std::initializer_list<int> bytes) {
  Payload p{};
  size_t i = 0;
  for (int b : bytes) p[i++] = static_cast<uint8_t>(b);
  return p;
}

uint64_t intel(const Payload& p, uint16_t start, uint8_t len) { return extract_bits(p, start, len, ByteOrder::kIntel); }
uint64_t motorola(const Payload& p, uint16_t start, uint8_t len) {
  return extract_bits(p, start, len, ByteOrder::kMotorola);
}

TEST(SignalBitsIntel, WholeByte) { EXPECT_EQ(intel(payload({0x00, 0xA5}), 8, 8), 0xA5u); }

TEST(SignalBitsIntel, NibbleAcrossAByteBoundary) {
  // bits 4..11: high nibble of byte 0 is the low nibble of the value.
  EXPECT_EQ(intel(payload({0xA0, 0x05}), 4, 8), 0x5Au);
}

TEST(SignalBitsIntel, SixteenBitsSpanningThreeBytes) {
  // bits 12..27: byte1 high nibble (3), byte2 (0x12), byte3 low nibble (4).
  EXPECT_EQ(intel(payload({0x00, 0x30, 0x12, 0x04}), 12, 16), 0x4123u);
}

TEST(SignalBitsIntel, LittleEndianThirtyTwoBits) {
  EXPECT_EQ(intel(payload({0, 0, 0x78, 0x56, 0x34, 0x12}), 16, 32), 0x12345678u);
}

TEST(SignalBitsIntel, SixtyFourBits) {
  EXPECT_EQ(intel(payload({1, 2, 3, 4, 5, 6, 7, 8}), 0, 64), 0x0807060504030201u);
  // Unaligned 64-bit field: bits 4..67, needs a ninth byte.
  EXPECT_EQ(intel(payload({0x10, 0x32, 0x54, 0x76, 0x98, 0xBA, 0xDC, 0xFE, 0x0F}), 4, 64), 0xFFEDCBA987654321u);
  EXPECT_EQ(bytes_needed(4, 64, ByteOrder::kIntel), 9u);
}

TEST(SignalBitsIntel, SingleBit) {
  EXPECT_EQ(intel(payload({0x00, 0x40}), 14, 1), 1u);
  EXPECT_EQ(intel(payload({0x00, 0x40}), 13, 1), 0u);
}

TEST(SignalBitsMotorola, WholeByte) { EXPECT_EQ(motorola(payload({0xA5}), 7, 8), 0xA5u); }

TEST(SignalBitsMotorola, BigEndianSixteenBits) {
  // start bit 7 = MSB of byte 0; the LSB is bit 0 of byte 1.
  EXPECT_EQ(motorola(payload({0x12, 0x34}), 7, 16), 0x1234u);
}

TEST(SignalBitsMotorola, TwelveBitsFromTheTopOfByteZero) {
  // 7|12@0: byte0 all 8 bits, then bits 7..4 of byte 1.
  EXPECT_EQ(motorola(payload({0xAB, 0xC0}), 7, 12), 0xABCu);
}

TEST(SignalBitsMotorola, StartInTheMiddleOfAByte) {
  // 3|8@0: bits 3..0 of byte 0, then bits 7..4 of byte 1.
  EXPECT_EQ(motorola(payload({0x0A, 0xB0}), 3, 8), 0xABu);
  // 11|12@0: bits 3..0 of byte 1, then all of byte 2.
  EXPECT_EQ(motorola(payload({0xFF, 0xF5, 0x67}), 11, 12), 0x567u);
  EXPECT_EQ(bytes_needed(11, 12, ByteOrder::kMotorola), 3u);
}

TEST(SignalBitsMotorola, SixtyFourBits) {
  EXPECT_EQ(motorola(payload({1, 2, 3, 4, 5, 6, 7, 8}), 7, 64), 0x0102030405060708u);
  // 3|64@0: low nibble of byte 0, bytes 1..7, high nibble of byte 8.
  EXPECT_EQ(motorola(payload({0x0F, 0xED, 0xCB, 0xA9, 0x87, 0x65, 0x43, 0x21, 0x00}), 3, 64), 0xFEDCBA9876543210u);
  EXPECT_EQ(bytes_needed(3, 64, ByteOrder::kMotorola), 9u);
  EXPECT_EQ(bytes_needed(7, 64, ByteOrder::kMotorola), 8u);
}

TEST(SignalBits, ImpossibleFieldsNeedNoBytes) {
  EXPECT_EQ(bytes_needed(0, 0, ByteOrder::kIntel), 0u);
  EXPECT_EQ(bytes_needed(0, 65, ByteOrder::kIntel), 0u);
  EXPECT_EQ(bytes_needed(508, 8, ByteOrder::kIntel), 0u);  // runs past byte 63
  EXPECT_EQ(bytes_needed(504, 8, ByteOrder::kIntel), 64u);
  EXPECT_EQ(bytes_needed(504, 9, ByteOrder::kMotorola), 0u);  // LSB would be in byte 64
  EXPECT_EQ(bytes_needed(512, 1, ByteOrder::kIntel), 0u);
}

TEST(SignalBits, SignExtension) {
  EXPECT_EQ(sign_extend(0xFFF, 12), -1);
  EXPECT_EQ(sign_extend(0x800, 12), -2048);
  EXPECT_EQ(sign_extend(0x7FF, 12), 2047);
  EXPECT_EQ(sign_extend(1, 1), -1);
  EXPECT_EQ(sign_extend(0xFFFFFFFFFFFFFFFFu, 64), -1);
  EXPECT_EQ(sign_extend(0x8000000000000000u, 64), INT64_MIN);
}

// Insert then extract every placement on a 64-byte payload filled with a
// pattern: the field reads back and no other bit changes.
TEST(SignalBits, InsertExtractRoundTripLeavesOtherBitsAlone) {
  uint64_t state = 0x9E3779B97F4A7C15u;
  auto next = [&] {
    state ^= state << 13;
    state ^= state >> 7;
    state ^= state << 17;
    return state;
  };
  for (ByteOrder order : {ByteOrder::kIntel, ByteOrder::kMotorola}) {
    for (uint16_t start = 0; start < 512; start += 7) {
      for (int length : {1, 7, 8, 13, 16, 31, 32, 33, 63, 64}) {
        const auto len = static_cast<uint8_t>(length);
        if (bytes_needed(start, len, order) == 0) continue;
        Payload base;
        for (auto& b : base) b = static_cast<uint8_t>(next());
        const uint64_t mask = len == 64 ? ~uint64_t{0} : (uint64_t{1} << len) - 1;
        const uint64_t value = next() & mask;
        Payload p = base;
        insert_bits(p, start, len, order, value);
        ASSERT_EQ(extract_bits(p, start, len, order), value) << "start " << start << " len " << int{len};
        insert_bits(p, start, len, order, extract_bits(base, start, len, order));
        ASSERT_EQ(p, base) << "start " << start << " len " << int{len};
      }
    }
  }
}

}  // namespace
}  // namespace sinew::hal::can
