// The joint-level Tresca yield of an SPH elastic joint (docs/sph.md, "Tresca:
// eq. (3)-(4) at the joint"). Per particle, eq. (4) runs every substep in
// sph_step; this is what the joint does with the count: "when the density of
// a particle increases beyond the yield condition, the object is no longer
// subjected to force" (sph-elastic-joints-tresca, abstract).
#pragma once

#include <cstdint>

namespace sinew::sph {

struct JointYield {
  bool yielded = false;
  int64_t held_torque_q12 = 0;  // |load torque| when the yield began (rig unit x N, Q12); 0 when not yielded
};

inline int64_t magnitude_q12(int64_t torque) { return torque < 0 ? -torque : torque; }

// The load torque the joint takes this tick: the requested one, held at
// the yield's torque while the joint yields.
inline int64_t held_load_torque(const JointYield& y, int64_t requested_q12) {
  if (!y.yielded) return requested_q12;
  if (requested_q12 > y.held_torque_q12) return y.held_torque_q12;
  if (requested_q12 < -y.held_torque_q12) return -y.held_torque_q12;
  return requested_q12;
}

// The joint's yield after a tick in which `yielded_particles` particles
// yielded: it enters at yield_count of them, holding the torque it took; it
// leaves once no particle yields and the requested load has fallen to the
// held one (both have fallen back), so a load held above the limit keeps
// it held rather than chattering in and out. Without tresca it never yields.
inline JointYield next_joint_yield(const JointYield& y, bool tresca, uint32_t yielded_particles, uint32_t yield_count,
                                   int64_t requested_q12, int64_t applied_q12) {
  if (!tresca) return {};
  if (!y.yielded) {
    if (yielded_particles < yield_count) return {};
    return {true, magnitude_q12(applied_q12)};
  }
  if (yielded_particles == 0 && magnitude_q12(requested_q12) <= y.held_torque_q12) return {};
  return y;
}

}  // namespace sinew::sph
