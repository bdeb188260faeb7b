#include "radian_turns.hpp"

#include <array>
#include <cstddef>

#include "sim_core/fixed/wide.hpp"

namespace sinew::units::detail {

namespace {

// Bits 1..1216 after the binary point of 1/(2 pi) = 0.0010100010111110...,
// 32 per word, most significant first (floor(2^1216 / (2 pi)), computed with
// 1500-bit arithmetic). The largest double, (2^53 - 1) * 2^971, needs bits up
// to 971 + 192.
constexpr std::array<uint32_t, 38> kInvTwoPiBits = {
    0x28BE60DB, 0x9391054A, 0x7F09D5F4, 0x7D4D3770, 0x36D8A566, 0x4F10E410, 0x7F9458EA, 0xF7AEF158,
    0x6DC91B8E, 0x909374B8, 0x01924BBA, 0x82746487, 0x3F877AC7, 0x2C4A69CF, 0xBA208D7D, 0x4BAED121,
    0x3A671C09, 0xAD17DF90, 0x4E64758E, 0x60D4CE7D, 0x272117E2, 0xEF7E4A0E, 0xC7FE25FF, 0xF7816603,
    0xFBCBC462, 0xD6829B47, 0xDB4D9FB3, 0xC9F2C26D, 0xD3D18FD9, 0xA797FA8B, 0x5D49EEB1, 0xFAF97C5E,
    0xCF41CE7D, 0xE294A4BA, 0x9AFED7EC, 0x47E35742, 0x1580CC11, 0xBF1EDAEA,
};

constexpr int kTableBits = 32 * static_cast<int>(kInvTwoPiBits.size());

// Bit i after the binary point (1-based); zero outside the table (bits i <= 0
// are the integer part of 1/(2 pi), which is 0).
uint64_t bit(int i) {
  if (i < 1 || i > kTableBits) return 0;
  const auto word = static_cast<size_t>((i - 1) / 32);
  return (kInvTwoPiBits[word] >> (31 - (i - 1) % 32)) & 1u;
}

// Bits first..first+63 as one word, first bit most significant.
uint64_t bits64(int first) {
  uint64_t w = 0;
  for (int i = 0; i < 64; ++i) w = (w << 1) | bit(first + i);
  return w;
}

}  // namespace

TurnFraction turns_of_radians(uint64_t mantissa, int exponent) {
  // x / (2 pi) = mantissa * sum_i b_i 2^(exponent - i). Bits i <= exponent
  // give whole turns and drop out; bits exponent+1 .. exponent+192 form the
  // window c; the rest adds less than mantissa * 2^-192 turn.
  const uint64_t c_hi = bits64(exponent + 1);
  const uint64_t c_mid = bits64(exponent + 65);
  const uint64_t c_lo = bits64(exponent + 129);
  // mantissa * c modulo 2^192.
  const fx::U128 p_lo = fx::mul_u64(mantissa, c_lo);
  const fx::U128 p_mid = fx::mul_u64(mantissa, c_mid);
  const uint64_t p_hi = mantissa * c_hi;  // only its low word survives the modulo
  const uint64_t w2 = p_lo.lo;
  const uint64_t w1 = p_mid.lo + p_lo.hi;
  const uint64_t carry = w1 < p_lo.hi ? 1u : 0u;
  const uint64_t w0 = p_hi + p_mid.hi + carry;
  return {{w0, w1, w2}};
}

}  // namespace sinew::units::detail
