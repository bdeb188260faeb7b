// Raw bit fields of a CAN payload in DBC conventions.
//
// Intel (little-endian, "@1"): start_bit is the signal's least significant
// bit, numbered byte * 8 + bit (bit 0 = LSB of the byte); the signal runs to
// higher bit numbers.
// Motorola (big-endian, "@0"): start_bit is the signal's most significant
// bit in the same numbering; from there the signal runs towards bit 0 of that
// byte and continues at bit 7 of the next byte.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

namespace sinew::hal::can {

enum class ByteOrder : uint8_t { kIntel, kMotorola };

// Payload bytes the field touches (1 + index of its highest byte), or 0 if the
// field is impossible (length 0 or > 64, or Motorola running past bit 511).
size_t bytes_needed(uint16_t start_bit, uint8_t length, ByteOrder order);

// The field's raw bits, right-aligned. The caller guarantees the payload is
// at least bytes_needed() long (decoders check it per frame).
uint64_t extract_bits(std::span<const uint8_t> payload, uint16_t start_bit, uint8_t length, ByteOrder order);

// Writes the low `length` bits of `raw` into the field (encoders, tests).
void insert_bits(std::span<uint8_t> payload, uint16_t start_bit, uint8_t length, ByteOrder order, uint64_t raw);

// Two's complement sign extension of a `length`-bit field.
int64_t sign_extend(uint64_t raw, uint8_t length);

}  // namespace sinew::hal::can
