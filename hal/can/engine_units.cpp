#include "engine_units.hpp"

#include <cmath>
#include <numbers>

namespace sinew::hal::can {

namespace {
constexpr double kTwo32 = 4294967296.0;
constexpr double kTwo20 = 1048576.0;

double round_half_up(double x) { return std::floor(x + 0.5); }
}  // namespace

bool to_engine_value(double physical, PhysicalUnit unit, int32_t& out) {
  if (!std::isfinite(physical)) return false;
  if (unit == PhysicalUnit::kRigUnits) {
    const double q = round_half_up(physical * kTwo20);
    if (q < -2147483648.0 || q > 2147483647.0) return false;
    out = static_cast<int32_t>(q);
    return true;
  }
  const double turns = unit == PhysicalUnit::kDegrees ? physical / 360.0 : physical / (2.0 * std::numbers::pi);
  // Wrap to one turn first so the product stays exact enough, then round and
  // wrap again (rounding may land on 2^32).
  double steps = round_half_up((turns - std::floor(turns)) * kTwo32);
  if (steps >= kTwo32) steps -= kTwo32;
  out = static_cast<int32_t>(static_cast<uint32_t>(steps));  // binary angle, viewed signed
  return true;
}

double from_engine_value(int32_t value, PhysicalUnit unit) {
  switch (unit) {
    case PhysicalUnit::kRigUnits:
      return value / kTwo20;
    case PhysicalUnit::kDegrees:
      return value * (360.0 / kTwo32);
    case PhysicalUnit::kRadians:
      return value * (2.0 * std::numbers::pi / kTwo32);
  }
  return 0.0;
}

}  // namespace sinew::hal::can
