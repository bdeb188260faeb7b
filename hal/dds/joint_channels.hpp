// What a rig input is on a JointState: its joint name and the SI unit its
// engine value converts to. hal knows units, not what the joints do.
//   kRadian: a rotation DOF, a signed binary angle (2^32 a turn) <-> rad
//   kMetre:  a translation DOF, Len (Q12.20 rig units, one rig unit
//            2^length_exponent m) <-> m
//   kNewton: a force input, Q16.16 N <-> N, carried as the effort
//   kScalar: another external input, Q16.16 in its own unit, as position
#pragma once

#include <cstdint>
#include <string>

namespace sinew::hal::dds {

enum class JointUnit : uint8_t { kRadian, kMetre, kNewton, kScalar };

struct JointChannel {
  std::string name;  // the joint's name on the JointState
  JointUnit unit = JointUnit::kRadian;
};

// The engine value in SI (rad in [-pi, pi), m, N, or the scalar's unit).
double joint_value_to_si(int32_t value, JointUnit unit, int32_t length_exponent);

// The engine value of an SI value, correctly rounded (an angle reduced to
// one turn); false for a non-finite value or one beyond the engine's range
// (a length or Q16.16 value that would saturate).
bool joint_value_from_si(double si, JointUnit unit, int32_t length_exponent, int32_t* out);

}  // namespace sinew::hal::dds
