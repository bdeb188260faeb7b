#include "joint_channels.hpp"

#include <cmath>

#include "hal/units/float_to_fixed.hpp"

namespace sinew::hal::dds {

namespace {
constexpr int32_t kQ16 = 16;
}  // namespace

double joint_value_to_si(int32_t value, JointUnit unit, int32_t length_exponent) {
  switch (unit) {
    case JointUnit::kRadian:
      return units::angle_to_radians(static_cast<uint32_t>(value));
    case JointUnit::kMetre:
      return units::len_to_double(value, length_exponent);
    case JointUnit::kNewton:
    case JointUnit::kScalar:
      return units::fixed_to_double(value, kQ16);
  }
  return 0;
}

bool joint_value_from_si(double si, JointUnit unit, int32_t length_exponent, int32_t* out) {
  if (!std::isfinite(si)) return false;
  if (unit == JointUnit::kRadian) {
    const units::AngleResult a = units::angle_from_radians(si);
    if (a.has(units::kNotFinite)) return false;
    *out = static_cast<int32_t>(a.value);
    return true;
  }
  const units::FixedResult f =
      unit == JointUnit::kMetre ? units::to_len(si, length_exponent) : units::to_fixed(si, kQ16);
  if (f.has(units::kClamped) || f.has(units::kNotFinite)) return false;
  *out = f.value;
  return true;
}

}  // namespace sinew::hal::dds
