#include "joint_state_sink.hpp"

#include <dds/dds.h>

#include <limits>
#include <vector>

#include "dds_entity.hpp"
#include "qos.hpp"
#include "ros2_names.hpp"
#include "sensor_msgs/msg/JointState.h"

namespace sinew::hal::dds {

struct JointStateSink::Impl {
  DdsEntity participant, topic, writer;
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

JointStateSink::JointStateSink() : impl_(std::make_unique<Impl>()) {}
JointStateSink::~JointStateSink() = default;

bool JointStateSink::open(const JointStateSinkOptions& options, std::span<const JointChannel> channels,
                          int32_t length_exponent, std::string* error) {
  if (!ros2_topic_name(options.ros_namespace, options.topic, &dds_topic_, error)) return false;
  if (options.domain_id > kMaxDomainId)
    return *error = "domain_id " + std::to_string(options.domain_id) + " is beyond 232", false;
  Impl& s = *impl_;
  s.participant = DdsEntity(dds_create_participant(options.domain_id, nullptr, nullptr));
  if (!s.participant.valid())
    return *error = "DDS participant on domain " + std::to_string(options.domain_id) + ": " +
                    dds_error_text(s.participant.get()),
           false;
  s.topic = DdsEntity(dds_create_topic(s.participant.get(), &sensor_msgs_msg_dds__JointState__desc, dds_topic_.c_str(),
                                       nullptr, nullptr));
  if (!s.topic.valid()) return *error = "DDS topic " + dds_topic_ + ": " + dds_error_text(s.topic.get()), false;
  dds_qos_t* qos = joint_state_qos(options.depth);
  s.writer = DdsEntity(dds_create_writer(s.participant.get(), s.topic.get(), qos, nullptr));
  dds_delete_qos(qos);
  if (!s.writer.valid()) return *error = "DDS writer on " + dds_topic_ + ": " + dds_error_text(s.writer.get()), false;

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
  if (!s.writer.valid()) return ++failed_, false;
  constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
  const size_t n = std::min<size_t>(s.channels.size(), frame.input_count);
  for (size_t i = 0; i < n; ++i) {
    const JointChannel& c = s.channels[i];
    const double si = joint_value_to_si(frame.input_value[i], c.unit, s.length_exponent);
    s.position[i] = c.unit == JointUnit::kNewton ? kNaN : si;
    s.effort[i] = c.unit == JointUnit::kNewton ? si : kNaN;
  }
  const int64_t stamp = static_cast<int64_t>(frame.timestamp_ns) + s.stamp_offset_ns;
  const int64_t sec = stamp >= 0 ? stamp / 1'000'000'000 : (stamp - 999'999'999) / 1'000'000'000;
  s.sample.header.stamp.sec = static_cast<int32_t>(sec);
  s.sample.header.stamp.nanosec = static_cast<uint32_t>(stamp - sec * 1'000'000'000);
  const dds_return_t rc = dds_write(s.writer.get(), &s.sample);
  if (rc != DDS_RETCODE_OK) return ++failed_, false;
  ++written_;
  return true;
}

uint32_t JointStateSink::matched_readers() const {
  dds_publication_matched_status_t matched{};
  if (!impl_->writer.valid() || dds_get_publication_matched_status(impl_->writer.get(), &matched) != DDS_RETCODE_OK)
    return 0;
  return matched.current_count;
}

std::string JointStateSink::status_line() const {
  return "dds " + dds_topic_ + " (sensor_msgs/msg/JointState): " + std::to_string(written_) + " samples written, " +
         std::to_string(failed_) + " failed, " + std::to_string(matched_readers()) + " readers matched";
}

}  // namespace sinew::hal::dds
