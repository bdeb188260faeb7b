// Configuration of the default joint-stream protocol (docs/can-protocol.md):
// which CAN identifiers carry which joints, each joint's data ID, accepted
// range, counter tolerance and receive timeout. Built once at start-up.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace sinew::hal::can {

inline constexpr size_t kJointsPerFdFrame = 8;
// Default layout (the shipped sinew_joints.dbc describes it for 32 joints).
inline constexpr uint32_t kDefaultClassicBaseId = 0x100;  // joint i on 0x100 + i
inline constexpr uint32_t kDefaultFdBaseId = 0x180;       // joints 8g..8g+7 on 0x180 + g
inline constexpr uint16_t kDefaultDataIdBase = 0x5300;    // joint i has data ID 0x5300 + i
inline constexpr size_t kDefaultMaxJoints = 128;

struct JointChannel {
  uint16_t input = 0;       // rig input index the samples feed
  uint16_t data_id = 0;     // E2E data ID of this joint's record
  int32_t min = INT32_MIN;  // accepted value range, engine units, inclusive
  int32_t max = INT32_MAX;
  uint8_t max_counter_delta = 1;  // 1..14: largest accepted alive-counter step
  uint64_t period_ns = 0;         // expected send period
  uint64_t timeout_ns = 0;        // 0: 1.5 x period_ns (and never stale if that is 0 too)
};

struct JointFrame {
  uint32_t can_id = 0;
  bool extended = false;
  bool fd = false;  // false: classic CAN, exactly one joint; true: CAN FD, 1..8 joints by slot
  std::vector<JointChannel> joints;
};

struct JointStreamConfig {
  std::vector<JointFrame> frames;
};

// The timeout a joint is held to: timeout_ns, else 1.5 x period_ns.
uint64_t resolved_timeout_ns(const JointChannel& joint);

// Checks identifiers, slot counts, ranges, deltas, uniqueness of CAN IDs,
// data IDs and inputs. Returns false with a message naming the offender.
bool validate(const JointStreamConfig& config, std::string* error);

// The default layout for joints 0..joint_count-1 feeding inputs 0..n-1:
// classic (one frame per joint) or packed CAN FD (eight joints per frame).
JointStreamConfig default_joint_stream_config(size_t joint_count, bool fd, uint64_t period_ns);

}  // namespace sinew::hal::can
