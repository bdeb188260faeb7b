#include "joint_stream_config.hpp"

#include <algorithm>
#include <cstdio>

#include "can_frame.hpp"
#include "joint_record.hpp"

namespace sinew::hal::can {

namespace {

bool fail(std::string* error, const std::string& message) {
  if (error != nullptr) *error = message;
  return false;
}

std::string frame_name(const JointFrame& f) {
  char buf[32];
  std::snprintf(buf, sizeof buf, f.extended ? "0x%08X" : "0x%03X", f.can_id);
  return std::string("frame ") + buf;
}

}  // namespace

uint64_t resolved_timeout_ns(const JointChannel& joint) {
  if (joint.timeout_ns != 0) return joint.timeout_ns;
  return joint.period_ns + joint.period_ns / 2;
}

bool validate(const JointStreamConfig& config, std::string* error) {
  std::vector<uint64_t> frame_keys;
  std::vector<uint16_t> data_ids;
  std::vector<uint16_t> inputs;
  if (config.frames.empty()) return fail(error, "joint stream: no frames configured");
  for (const JointFrame& f : config.frames) {
    const uint32_t mask = f.extended ? kExtendedIdMask : kStandardIdMask;
    if ((f.can_id & ~mask) != 0) return fail(error, frame_name(f) + ": identifier does not fit its format");
    frame_keys.push_back((static_cast<uint64_t>(f.extended) << 32) | f.can_id);
    const size_t max_joints = f.fd ? kJointsPerFdFrame : 1;
    if (f.joints.empty() || f.joints.size() > max_joints) {
      return fail(error, frame_name(f) + (f.fd ? ": a CAN FD frame carries 1..8 joints"
                                               : ": a classic frame carries exactly 1 joint"));
    }
    for (const JointChannel& j : f.joints) {
      if (j.min > j.max)
        return fail(error, frame_name(f) + ": joint for input " + std::to_string(j.input) + " has min > max");
      if (j.max_counter_delta < 1 || j.max_counter_delta > kAliveCounterMax) {
        return fail(error, frame_name(f) + ": max_counter_delta must be 1..14");
      }
      data_ids.push_back(j.data_id);
      inputs.push_back(j.input);
    }
  }
  auto has_duplicate = [](auto v) {
    std::sort(v.begin(), v.end());
    return std::adjacent_find(v.begin(), v.end()) != v.end();
  };
  if (has_duplicate(frame_keys)) return fail(error, "joint stream: a CAN identifier is configured twice");
  if (has_duplicate(data_ids)) return fail(error, "joint stream: a data ID is configured twice");
  if (has_duplicate(inputs)) return fail(error, "joint stream: an input is fed by two joints");
  return true;
}

JointStreamConfig default_joint_stream_config(size_t joint_count, bool fd, uint64_t period_ns) {
  JointStreamConfig config;
  joint_count = std::min(joint_count, kDefaultMaxJoints);
  for (size_t i = 0; i < joint_count; ++i) {
    JointChannel j;
    j.input = static_cast<uint16_t>(i);
    j.data_id = static_cast<uint16_t>(kDefaultDataIdBase + i);
    j.period_ns = period_ns;
    if (!fd) {
      config.frames.push_back({static_cast<uint32_t>(kDefaultClassicBaseId + i), false, false, {j}});
    } else {
      if (i % kJointsPerFdFrame == 0) {
        config.frames.push_back({static_cast<uint32_t>(kDefaultFdBaseId + i / kJointsPerFdFrame), false, true, {}});
      }
      config.frames.back().joints.push_back(j);
    }
  }
  return config;
}

}  // namespace sinew::hal::can
