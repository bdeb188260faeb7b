#include "frame_sink.hpp"

#include <dds/dds.h>

#include <algorithm>
#include <vector>

#include "dds_writer.hpp"
#include "qos.hpp"
#include "sinew/msg/Frame.h"

namespace sinew::hal::dds {

struct FrameSink::Impl {
  std::vector<std::string> input_names, stage_names;
  std::vector<char*> input_ptrs, stage_ptrs;
  std::vector<uint8_t> input_status;
  std::vector<uint32_t> stage_ns;
  std::string frame_id;
  int64_t stamp_offset_ns = 0;
  sinew_msg_dds__Frame_ sample{};
};

FrameSink::FrameSink() : TopicSink("dds-frame", "sinew/msg/Frame"), impl_(std::make_unique<Impl>()) {}
FrameSink::~FrameSink() = default;

bool FrameSink::open(const FrameSinkOptions& options, std::span<const std::string> input_names,
                     std::span<const std::string> stage_names, std::string* error) {
  Impl& s = *impl_;
  if (!writer().open(options.domain_id, options.ros_namespace, options.topic, &sinew_msg_dds__Frame__desc,
                     joint_state_qos(options.depth), error))
    return false;
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
  if (!writer().valid()) return reject();
  std::fill(s.input_status.begin(), s.input_status.end(), uint8_t{0});
  std::fill(s.stage_ns.begin(), s.stage_ns.end(), 0u);
  if (frame.input_status != nullptr)
    std::copy_n(frame.input_status, std::min<size_t>(frame.input_count, s.input_status.size()), s.input_status.begin());
  if (frame.stage_ns != nullptr)
    std::copy_n(frame.stage_ns, std::min<size_t>(frame.stage_count, s.stage_ns.size()), s.stage_ns.begin());
  s.sample.tick = frame.tick;
  const Ros2Time stamp = ros2_time(static_cast<int64_t>(frame.timestamp_ns) + s.stamp_offset_ns);
  s.sample.header.stamp = {stamp.sec, stamp.nanosec};
  return publish(&s.sample);
}

}  // namespace sinew::hal::dds
