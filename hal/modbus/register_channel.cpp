#include "register_channel.hpp"

#include <cmath>

namespace sinew::hal::modbus {

namespace {

constexpr double kTwo32 = 4294967296.0;

double engine_per_unit(Quantity q) {
  switch (q) {
    case Quantity::kAngle: return kTwo32 / 360.0;
    case Quantity::kTranslation: return 1048576.0;  // 2^20
    case Quantity::kForce: return 65536.0;          // 2^16
  }
  return 1.0;
}

std::string label(const ChannelConfig& c) {
  return "channel " + (c.name.empty() ? "for input " + std::to_string(c.input) : "'" + c.name + "'");
}

}  // namespace

double representable_limit(Quantity q) {
  switch (q) {
    case Quantity::kAngle: return 180.0;
    case Quantity::kTranslation: return 2048.0;
    case Quantity::kForce: return 32768.0;
  }
  return 0.0;
}

const char* quantity_unit(Quantity q) {
  switch (q) {
    case Quantity::kAngle: return "deg";
    case Quantity::kTranslation: return "rig units";
    case Quantity::kForce: return "N";
  }
  return "";
}

int64_t decode_raw(const ChannelConfig& c, std::span<const uint16_t> regs) {
  if (c.width == RegisterWidth::k16) {
    const uint16_t r = regs[0];
    return c.is_signed ? int64_t{static_cast<int16_t>(r)} : int64_t{r};
  }
  const bool high_first = c.word_order == WordOrder::kHighWordFirst;
  const uint32_t high = high_first ? regs[0] : regs[1];
  const uint32_t low = high_first ? regs[1] : regs[0];
  const uint32_t u = (high << 16) | low;
  return c.is_signed ? int64_t{static_cast<int32_t>(u)} : int64_t{u};
}

double to_physical(const ChannelConfig& c, int64_t raw) { return static_cast<double>(raw) * c.scale + c.offset; }

int32_t to_engine(Quantity q, double x) {
  // Round half up, as everywhere in the engine; saturate instead of wrapping.
  const double v = std::floor(x * engine_per_unit(q) + 0.5);
  if (v >= 2147483647.0) return INT32_MAX;
  if (v <= -2147483648.0) return INT32_MIN;
  return static_cast<int32_t>(v);
}

Conversion convert(const ChannelConfig& c, std::span<const uint16_t> regs) {
  Conversion out;
  out.physical = to_physical(c, decode_raw(c, regs));
  // Written so that NaN fails too.
  if (!(out.physical >= c.min && out.physical <= c.max)) return out;
  out.accepted = true;
  out.value = to_engine(c.quantity, out.physical);
  return out;
}

bool validate(const ChannelConfig& c, std::string* error) {
  if (!std::isfinite(c.scale) || c.scale == 0.0) return *error = label(c) + ": scale must be finite and non-zero", false;
  if (!std::isfinite(c.offset)) return *error = label(c) + ": offset must be finite", false;
  if (!std::isfinite(c.min) || !std::isfinite(c.max) || c.min > c.max)
    return *error = label(c) + ": range needs finite min <= max", false;
  const double limit = representable_limit(c.quantity);
  if (c.min < -limit || c.max > limit)
    return *error = label(c) + ": range must lie within +-" + std::to_string(static_cast<int>(limit)) + " " +
                    quantity_unit(c.quantity) + " (the engine format's span)",
           false;
  if (uint32_t{c.address} + register_count(c.width) > 65536u)
    return *error = label(c) + ": registers run past address 65535", false;
  return true;
}

}  // namespace sinew::hal::modbus
