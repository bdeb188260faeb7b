#include "register_channel.hpp"

#include <cmath>

#include "hal/units/float_to_fixed.hpp"

namespace sinew::hal::modbus {

namespace {

std::string label(const ChannelConfig& c) {
  return "channel " + (c.name.empty() ? "for input " + std::to_string(c.input) : "'" + c.name + "'");
}

}  // namespace

double representable_limit(Quantity q) {
  switch (q) {
    case Quantity::kAngle:
      return 180.0;
    case Quantity::kTranslation:
      return 2048.0;
    case Quantity::kForce:
      return 32768.0;
  }
  return 0.0;
}

const char* quantity_unit(Quantity q) {
  switch (q) {
    case Quantity::kAngle:
      return "deg";
    case Quantity::kTranslation:
      return "rig units";
    case Quantity::kForce:
      return "N";
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
  // hal/units' conversions (correctly rounded, half up, saturating). Angles
  // saturate too: +180 is the largest signed angle, not -180, so the
  // channel's range keeps its order.
  switch (q) {
    case Quantity::kAngle:
      return units::signed_angle_from_degrees(x).value;
    case Quantity::kTranslation:
      return units::to_len(x, 0).value;  // Q12.20 rig units
    case Quantity::kForce:
      return units::to_fixed(x, 16).value;  // Q15.16 newtons
  }
  return 0;
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
  if (!std::isfinite(c.scale) || c.scale == 0.0)
    return *error = label(c) + ": scale must be finite and non-zero", false;
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
