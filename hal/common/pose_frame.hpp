// What every output sink receives once per tick: the deformed pose, as plain
// integer arrays (no physics types), plus per-joint status and health.
#pragma once

#include <cstdint>

namespace sinew::hal {

enum JointStatus : uint8_t {
  kJointOk = 0,
  kJointClampedStatus = 1u << 0,  // commanded beyond a limit, clamped
  kJointStale = 1u << 1,          // no valid sample within its timeout: holding the last good value
  kJointRejected = 1u << 2,       // a sample was rejected this tick (CRC, counter, range)
  kJointYielded = 1u << 3,        // a physical layer's joint yields this tick (SPH Tresca yield, docs/sph.md)
  // A source has delivered this input (since the run began): a measured DOF,
  // which the rig's synergies and SPH joints leave as measured
  // (docs/rig-format.md, docs/sph.md). Replays rebuild the run from it.
  kJointMeasured = 1u << 4,
};

struct PoseFrame {
  // The tick's slot on the schedule (a skipped live tick leaves a gap; the
  // same slot carries the same number live, in replay and offline).
  uint64_t tick = 0;
  // The tick's time, ns: its nominal time on the schedule (CLOCK_MONOTONIC
  // live; counted from 0 in offline and replay runs), or, for a tick a
  // trigger started early, the time it started.
  uint64_t timestamp_ns = 0;
  int32_t length_exponent = 0;  // one rig unit = 2^e metres; positions are Q12.20 rig units
  uint32_t vertex_count = 0;
  const int32_t* position[3] = {nullptr, nullptr, nullptr};  // SoA, vertex_count each
  const int32_t* normal[3] = {nullptr, nullptr, nullptr};    // SoA Q2.30, or null
  uint32_t input_count = 0;
  const int32_t* input_value = nullptr;   // value per input (the rig's, then external ones), as applied this tick
  const uint8_t* input_status = nullptr;  // JointStatus bits per input
  // Each pipeline stage's time this tick, ns (saturated at 2^32 - 1; 0: it
  // did not run), in the order of the stage table the runtime names; or none.
  uint32_t stage_count = 0;
  const uint32_t* stage_ns = nullptr;
};

}  // namespace sinew::hal
