#include "engine_units.hpp"

#include "hal/units/float_to_fixed.hpp"

namespace sinew::hal::can {

// The conversions are hal/units' (correctly rounded, half up, exact for
// every double); this file only maps the signal's unit onto them.
bool to_engine_value(double physical, PhysicalUnit unit, int32_t& out) {
  switch (unit) {
    case PhysicalUnit::kRigUnits: {
      const units::FixedResult r = units::to_len(physical, 0);
      if (r.has(units::kNotFinite) || r.has(units::kClamped)) return false;
      out = r.value;
      return true;
    }
    case PhysicalUnit::kDegrees:
    case PhysicalUnit::kRadians: {
      const units::AngleResult a =
          unit == PhysicalUnit::kDegrees ? units::angle_from_degrees(physical) : units::angle_from_radians(physical);
      if (a.has(units::kNotFinite)) return false;
      out = static_cast<int32_t>(a.value);  // binary angle, viewed signed
      return true;
    }
  }
  return false;
}

double from_engine_value(int32_t value, PhysicalUnit unit) {
  switch (unit) {
    case PhysicalUnit::kRigUnits:
      return units::len_to_double(value, 0);
    case PhysicalUnit::kDegrees:
      return units::angle_to_degrees(static_cast<uint32_t>(value));
    case PhysicalUnit::kRadians:
      return units::angle_to_radians(static_cast<uint32_t>(value));
  }
  return 0.0;
}

}  // namespace sinew::hal::can
