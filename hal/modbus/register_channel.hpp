// One mapped value of a Modbus device: where it lives (table, address, one or
// two registers), how to read it (signedness, word order, scale and offset to
// a physical value) and which rig input it feeds. Converting a reading gives
// the engine's integer format (docs/numerics.md) or a range rejection.
#pragma once

#include <cstdint>
#include <span>
#include <string>

namespace sinew::hal::modbus {

enum class RegisterTable : uint8_t {
  kHolding,  // function 0x03
  kInput,    // function 0x04
};

enum class RegisterWidth : uint8_t {
  k16,  // one register
  k32,  // two consecutive registers
};

// Order of the two 16-bit words of a 32-bit value (bytes within a register
// are always big-endian, as the protocol defines).
enum class WordOrder : uint8_t {
  kHighWordFirst,  // first register holds bits 31..16 ("ABCD")
  kLowWordFirst,   // first register holds bits 15..0 ("CDAB")
};

// What the physical value is, which fixes its engine format:
enum class Quantity : uint8_t {
  kAngle,        // degrees -> signed binary angle (2^32 = one turn)
  kTranslation,  // rig units -> Q12.20
  kForce,        // newtons -> Q16.16
};

struct ChannelConfig {
  std::string name;    // for messages; may be empty
  uint16_t input = 0;  // rig input index the samples feed
  RegisterTable table = RegisterTable::kHolding;
  uint16_t address = 0;  // protocol address of the first register (0-based)
  RegisterWidth width = RegisterWidth::k16;
  WordOrder word_order = WordOrder::kHighWordFirst;  // 32-bit values only
  bool is_signed = true;                             // two's complement raw value
  double scale = 1.0;                                // physical = raw * scale + offset
  double offset = 0.0;
  Quantity quantity = Quantity::kAngle;
  double min = -180.0;  // accepted physical range, inclusive; outside is rejected
  double max = 180.0;
};

inline constexpr uint16_t register_count(RegisterWidth w) { return w == RegisterWidth::k32 ? 2 : 1; }

// The physical range the engine format can hold: [-180, 180] degrees,
// [-2048, 2048] rig units, [-32768, 32768] newtons (the upper edge saturates
// to INT32_MAX, one LSB short).
double representable_limit(Quantity q);
const char* quantity_unit(Quantity q);

// The raw integer in `regs` (register_count(width) registers).
int64_t decode_raw(const ChannelConfig& c, std::span<const uint16_t> regs);
// raw * scale + offset.
double to_physical(const ChannelConfig& c, int64_t raw);
// Physical value in engine units: x * 2^32/360, x * 2^20 or x * 2^16, rounded
// half up and saturated to int32. `x` must be finite.
int32_t to_engine(Quantity q, double x);

struct Conversion {
  bool accepted = false;  // false: outside [min, max] (or not a number)
  int32_t value = 0;      // engine units when accepted
  double physical = 0.0;
};
Conversion convert(const ChannelConfig& c, std::span<const uint16_t> regs);

// Checks scale, offset and range; false with a message naming the channel.
bool validate(const ChannelConfig& c, std::string* error);

}  // namespace sinew::hal::modbus
