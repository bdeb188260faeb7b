#include "signal_bits.hpp"

namespace sinew::hal::can {

namespace {

constexpr unsigned kMaxBit = 64 * 8;  // largest payload: CAN FD, 64 bytes

// Position of the next less significant bit of a Motorola field.
unsigned motorola_next(unsigned bit) { return (bit % 8 == 0) ? bit + 15 : bit - 1; }

unsigned bit_at(std::span<const uint8_t> payload, unsigned bit) {
  return (static_cast<unsigned>(payload[bit / 8]) >> (bit % 8)) & 1u;
}

// Position of the field's least significant bit (Motorola) or most significant (Intel).
unsigned far_end(uint16_t start_bit, uint8_t length, ByteOrder order) {
  if (order == ByteOrder::kIntel) return unsigned{start_bit} + length - 1u;
  unsigned bit = start_bit;
  for (unsigned k = 1; k < length; ++k) bit = motorola_next(bit);
  return bit;
}

}  // namespace

size_t bytes_needed(uint16_t start_bit, uint8_t length, ByteOrder order) {
  if (length == 0 || length > 64 || start_bit >= kMaxBit) return 0;
  const unsigned end = far_end(start_bit, length, order);
  if (end >= kMaxBit) return 0;
  // Both orders end in their highest byte: Intel at its MSB, Motorola at its LSB.
  return end / 8 + 1;
}

uint64_t extract_bits(std::span<const uint8_t> payload, uint16_t start_bit, uint8_t length, ByteOrder order) {
  uint64_t raw = 0;
  if (order == ByteOrder::kIntel) {
    for (unsigned k = 0; k < length; ++k) {
      const unsigned bit = unsigned{start_bit} + k;
      raw |= static_cast<uint64_t>(bit_at(payload, bit)) << k;
    }
    return raw;
  }
  unsigned bit = start_bit;
  for (unsigned k = 0; k < length; ++k) {
    raw = (raw << 1) | bit_at(payload, bit);
    bit = motorola_next(bit);
  }
  return raw;
}

void insert_bits(std::span<uint8_t> payload, uint16_t start_bit, uint8_t length, ByteOrder order, uint64_t raw) {
  auto put = [&](unsigned bit, unsigned value) {
    const auto mask = static_cast<uint8_t>(1u << (bit % 8));
    payload[bit / 8] = static_cast<uint8_t>(value != 0 ? (payload[bit / 8] | mask) : (payload[bit / 8] & ~mask));
  };
  if (order == ByteOrder::kIntel) {
    for (unsigned k = 0; k < length; ++k) put(unsigned{start_bit} + k, static_cast<unsigned>((raw >> k) & 1u));
    return;
  }
  unsigned bit = start_bit;
  for (unsigned k = 0; k < length; ++k) {
    put(bit, static_cast<unsigned>((raw >> (length - 1u - k)) & 1u));
    bit = motorola_next(bit);
  }
}

int64_t sign_extend(uint64_t raw, uint8_t length) {
  if (length == 0 || length >= 64) return static_cast<int64_t>(raw);
  const uint64_t sign = uint64_t{1} << (length - 1u);
  const uint64_t field = raw & ((uint64_t{1} << length) - 1u);
  return static_cast<int64_t>((field ^ sign) - sign);  // wraps modulo 2^64, then two's complement
}

}  // namespace sinew::hal::can
