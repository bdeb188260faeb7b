// What every input backend delivers: timestamped joint values, already in the
// engine's units, with a per-sample status. hal knows nothing of the physics:
// only the input index, the value and when it arrived.
#pragma once

#include <cstddef>
#include <cstdint>

namespace sinew::hal {

// Value formats (docs/numerics.md): a rotational input is a signed binary
// angle (2^32 = one turn); a translational one is Q12.20 rig units.
struct JointSample {
  uint16_t input = 0;  // index into the rig's inputs
  int32_t value = 0;
  uint64_t timestamp_ns = 0;  // arrival time (kernel timestamp where available), CLOCK_MONOTONIC
  uint8_t status = 0;         // SampleStatus bits reported by the sender
};

enum SampleStatus : uint8_t {
  kSampleOk = 0,
  kSampleSenderFault = 1u << 0,  // the sender flagged its own measurement as bad
};

// Why a received frame or sample was rejected (counted per source).
enum class RejectReason : uint8_t {
  kBadCrc,
  kRepeatedCounter,
  kCounterJump,
  kOutOfRange,
  kMalformed,
  kUnknownId,
  kCount,
};

const char* reject_reason_name(RejectReason r);

// The reason as an index into per-reason counter arrays.
constexpr size_t reason_index(RejectReason r) { return static_cast<size_t>(r); }

}  // namespace sinew::hal
