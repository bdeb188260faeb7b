#include "frame_sink.hpp"

#include <dds/dds.h>

#include <algorithm>
#include <vector>

#include "dds_entity.hpp"
#include "qos.hpp"
#include "ros2_names.hpp"
#include "sinew/msg/Frame.h"

namespace sinew::hal::dds {

struct FrameSink::Impl {
  DdsEntity participant, topic, writer;
  std::vector<std::string> input_names, stage_names;
  std::vector<char*> input_ptrs, stage_ptrs;
  std::vector<uint8_t> input_status;
  std::vector<uint32_t> stage_ns;
  std::string frame_id;
  int64_t stamp_offset_ns = 0;
  sinew_msg_dds__Frame_ sample{};
};

FrameSink::FrameSink() : impl_(std::make_unique<Impl>()) {}
FrameSink::~FrameSink() = default;

bool FrameSink::open(const FrameSinkOptions& options, std::span<const std::string> input_names,
                     std::span<const std::string> stage_names, std::string* error) {
  if (!ros2_topic_name(options.ros_namespace, options.topic, &dds_topic_, error)) return false;
  if (options.domain_id > kMaxDomainId)
    return *error = "domain_id " + std::to_string(options.domain_id) + " is beyond 232", false;
  Impl& s = *impl_;
  s.participant = DdsEntity(dds_create_participant(options.domain_id, nullptr, nullptr));
  if (!s.participant.valid())
    return *error = "DDS participant on domain " + std::to_string(options.domain_id) + ": " +
                    dds_error_text(s.participant.get()),
           false;
  s.topic = DdsEntity(
      dds_create_topic(s.participant.get(), &sinew_msg_dds__Frame__desc, dds_topic_.c_str(), nullptr, nullptr));
  if (!s.topic.valid()) return *error = "DDS topic " + dds_topic_ + ": " + dds_error_text(s.topic.get()), false;
  dds_qos_t* qos = joint_state_qos(options.depth);
  s.writer = DdsEntity(dds_create_writer(s.participant.get(), s.topic.get(), qos, nullptr));
  dds_delete_qos(qos);
  if (!s.writer.valid()) return *error = "DDS writer on " + dds_topic_ + ": " + dds_error_text(s.writer.get()), false;
  s.input_names.assign(input_names.begin(), input_names.end());
  s.stage_names.assign(stage_names.begin(), stage_names.end());
  s.input_ptrs.clear();
  for (std::string& n : s.input_names) s.input_ptrs.push_back(n.data());
  s.stage_ptrs.clear();
  for (std::string& n : s.stage_names) s.stage_ptrs.push_back(n.data());
  s.input_status.assign(input_names.size(), 0);
  s.stage_ns.assign(stage_names.size(), 0);
  s.frame_id = options.frame_id;
  s.stamp_offset_ns = options.stamp_offset_ns;
  const auto inputs = static_cast<uint32_t>(input_names.size());
  const auto stages = static_cast<uint32_t>(stage_names.size());
  s.sample = {};
  s.sample.header.frame_id = s.frame_id.data();
  s.sample.input_names = {inputs, inputs, s.input_ptrs.data(), false};
  s.sample.input_status = {inputs, inputs, s.input_status.data(), false};
  s.sample.stage_names = {stages, stages, s.stage_ptrs.data(), false};
  s.sample.stage_ns = {stages, stages, s.stage_ns.data(), false};
  return true;
}

bool FrameSink::write(const PoseFrame& frame) {
  Impl& s = *impl_;
  if (!s.writer.valid()) return ++failed_, false;
  std::fill(s.input_status.begin(), s.input_status.end(), uint8_t{0});
  std::fill(s.stage_ns.begin(), s.stage_ns.end(), 0u);
  if (frame.input_status != nullptr)
    std::copy_n(frame.input_status, std::min<size_t>(frame.input_count, s.input_status.size()), s.input_status.begin());
  if (frame.stage_ns != nullptr)
    std::copy_n(frame.stage_ns, std::min<size_t>(frame.stage_count, s.stage_ns.size()), s.stage_ns.begin());
  s.sample.tick = frame.tick;
  const int64_t stamp = static_cast<int64_t>(frame.timestamp_ns) + s.stamp_offset_ns;
  const int64_t sec = stamp >= 0 ? stamp / 1'000'000'000 : (stamp - 999'999'999) / 1'000'000'000;
  s.sample.header.stamp.sec = static_cast<int32_t>(sec);
  s.sample.header.stamp.nanosec = static_cast<uint32_t>(stamp - sec * 1'000'000'000);
  if (dds_write(s.writer.get(), &s.sample) != DDS_RETCODE_OK) return ++failed_, false;
  ++written_;
  return true;
}

uint32_t FrameSink::matched_readers() const {
  dds_publication_matched_status_t matched{};
  if (!impl_->writer.valid() || dds_get_publication_matched_status(impl_->writer.get(), &matched) != DDS_RETCODE_OK)
    return 0;
  return matched.current_count;
}

std::string FrameSink::status_line() const {
  return "dds " + dds_topic_ + " (sinew/msg/Frame): " + std::to_string(written_) + " written, " +
         std::to_string(failed_) + " failed, " + std::to_string(matched_readers()) + " readers matched";
}

}  // namespace sinew::hal::dds
