// CRC-32C against RFC 3720's test vectors (B.4) and a bitwise reference at
// every length, start offset and split: the sliced loop and its byte tail
// must agree with the polynomial one byte at a time.
#include "sim_core/rig/crc32c.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <cstring>
#include <numeric>
#include <vector>

namespace {

using sinew::rig::crc32c;

uint32_t crc32c_bitwise(const uint8_t* data, size_t size) {
  uint32_t c = 0xFFFFFFFFu;
  for (size_t i = 0; i < size; ++i) {
    c ^= data[i];
    for (int k = 0; k < 8; ++k) c = (c & 1u) ? (c >> 1) ^ 0x82F63B78u : c >> 1;
  }
  return ~c;
}

TEST(Crc32c, Rfc3720Vectors) {
  const char* check = "123456789";
  EXPECT_EQ(crc32c(0, reinterpret_cast<const uint8_t*>(check), 9), 0xE3069283u);
  std::vector<uint8_t> b(32, 0x00);
  EXPECT_EQ(crc32c(0, b.data(), b.size()), 0x8A9136AAu);
  std::fill(b.begin(), b.end(), uint8_t{0xFF});
  EXPECT_EQ(crc32c(0, b.data(), b.size()), 0x62A8AB43u);
  std::iota(b.begin(), b.end(), uint8_t{0});
  EXPECT_EQ(crc32c(0, b.data(), b.size()), 0x46DD794Eu);
  for (size_t i = 0; i < 32; ++i) b[i] = static_cast<uint8_t>(31 - i);
  EXPECT_EQ(crc32c(0, b.data(), b.size()), 0x113FDB5Cu);
}

TEST(Crc32c, EveryLengthOffsetAndSplitMatchesTheBitwisePolynomial) {
  std::vector<uint8_t> bytes(96);
  uint32_t x = 0x12345678u;
  for (uint8_t& v : bytes) {
    x = x * 1664525u + 1013904223u;
    v = static_cast<uint8_t>(x >> 24);
  }
  for (size_t offset = 0; offset < 8; ++offset) {
    for (size_t size = 0; offset + size <= bytes.size(); ++size) {
      const uint8_t* p = bytes.data() + offset;
      const uint32_t expected = crc32c_bitwise(p, size);
      ASSERT_EQ(crc32c(0, p, size), expected) << "offset " << offset << " size " << size;
      for (size_t split = 0; split <= size; split += 3)
        ASSERT_EQ(crc32c(crc32c(0, p, split), p + split, size - split), expected)
            << "offset " << offset << " size " << size << " split " << split;
    }
  }
}

}  // namespace
