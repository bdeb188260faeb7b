// sinew's own frame on DDS, one sample a tick (docs/ros2.md, "sinew's
// frame"; hal/dds/idl/sinew/msg/Frame.idl): the tick's slot, each input's
// health bits and each pipeline stage's time, for a host that monitors
// several boards. Reliable, keep-last `depth`, volatile, as the joint
// states. hal knows no stages: their names come in at open().
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "topic_sink.hpp"

namespace sinew::hal::dds {

struct FrameSinkOptions {
  uint32_t domain_id = 0;
  std::string ros_namespace;
  std::string topic = "sinew_frame";
  std::string frame_id;
  uint32_t depth = 10;
  int64_t stamp_offset_ns = 0;  // as JointStateSinkOptions::stamp_offset_ns
};

class FrameSink : public TopicSink {
 public:
  FrameSink();
  ~FrameSink() override;

  // input_names: one per frame input; stage_names: one per frame stage time.
  bool open(const FrameSinkOptions& options, std::span<const std::string> input_names,
            std::span<const std::string> stage_names, std::string* error);

  bool write(const PoseFrame& frame) override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace sinew::hal::dds
