#include "joint_sample.hpp"

namespace sinew::hal {

const char* reject_reason_name(RejectReason r) {
  switch (r) {
    case RejectReason::kBadCrc:
      return "bad-crc";
    case RejectReason::kRepeatedCounter:
      return "repeated-counter";
    case RejectReason::kCounterJump:
      return "counter-jump";
    case RejectReason::kOutOfRange:
      return "out-of-range";
    case RejectReason::kMalformed:
      return "malformed";
    case RejectReason::kUnknownId:
      return "unknown-id";
    case RejectReason::kCount:
      break;
  }
  return "unknown";
}

}  // namespace sinew::hal
