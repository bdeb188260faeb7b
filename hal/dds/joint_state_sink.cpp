#include "joint_state_sink.hpp"

#include <dds/dds.h>

#include <limits>
#include <vector>

#include "dds_writer.hpp"
#include "qos.hpp"
#include "sensor_msgs/msg/JointState.h"

namespace sinew::hal::dds {

struct JointStateSink::Impl {
  std::vector<JointChannel> channels;
  int32_t length_exponent = 0;
  int64_t stamp_offset_ns = 0;
  std::string frame_id;
  std::vector<std::string> names;
  std::vector<char*> name_ptrs;
  std::vector<double> position, effort;
  bool any_force = false;
  sensor_msgs_msg_dds__JointState_ sample{};
};

JointStateSink::JointStateSink() : TopicSink("dds", "sensor_msgs/msg/JointState"), impl_(std::make_unique<Impl>()) {}
JointStateSink::~JointStateSink() = default;

bool JointStateSink::open(const JointStateSinkOptions& options, std::span<const JointChannel> channels,
                          int32_t length_exponent, std::string* error) {
  Impl& s = *impl_;
  if (!writer().open(options.domain_id, options.ros_namespace, options.topic, &sensor_msgs_msg_dds__JointState__desc,
                     joint_state_qos(options.depth), error))
    return false;

  s.channels.assign(channels.begin(), channels.end());
  s.length_exponent = length_exponent;
  s.stamp_offset_ns = options.stamp_offset_ns;
  s.frame_id = options.frame_id;
  s.names.clear();
  for (const JointChannel& c : channels) s.names.push_back(c.name);
  s.name_ptrs.clear();
  for (std::string& n : s.names) s.name_ptrs.push_back(n.data());
  s.position.assign(channels.size(), 0);
  s.effort.assign(channels.size(), 0);
  s.any_force = false;
  for (const JointChannel& c : channels) s.any_force |= c.unit == JointUnit::kNewton;
  const auto count = static_cast<uint32_t>(channels.size());
  s.sample = {};
  s.sample.header.frame_id = s.frame_id.data();
  s.sample.name = {count, count, s.name_ptrs.data(), false};
  s.sample.position = {count, count, s.position.data(), false};
  s.sample.velocity = {0, 0, nullptr, false};
  s.sample.effort = s.any_force ? dds_sequence_double{count, count, s.effort.data(), false}
                                : dds_sequence_double{0, 0, nullptr, false};
  return true;
}

bool JointStateSink::write(const PoseFrame& frame) {
  Impl& s = *impl_;
  if (!writer().valid()) return reject();
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  const size_t n = std::min<size_t>(s.channels.size(), frame.input_count);
  for (size_t i = 0; i < n; ++i) {
    const JointChannel& c = s.channels[i];
    const double si = joint_value_to_si(frame.input_value[i], c.unit, s.length_exponent);
    s.position[i] = c.unit == JointUnit::kNewton ? kNaN : si;
    s.effort[i] = c.unit == JointUnit::kNewton ? si : kNaN;
  }
  const Ros2Time stamp = ros2_time(static_cast<int64_t>(frame.timestamp_ns) + s.stamp_offset_ns);
  s.sample.header.stamp = {stamp.sec, stamp.nanosec};
  return publish(&s.sample);
}

}  // namespace sinew::hal::dds
