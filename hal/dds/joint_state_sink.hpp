// The applied inputs as ROS 2's sensor_msgs/msg/JointState on DDS, one
// sample a frame (docs/ros2.md): joint names, positions in rad or m, and
// efforts in N where an input is a force (NaN for the others, and a
// force's position NaN: every array has one entry per name, as the message
// asks). Reliable, keep-last `depth`, volatile: ROS 2's default QoS, which
// `ros2 topic echo` and robot_state_publisher use.
//
// write() runs on the sink's I/O thread (firmware's AsyncSink); Cyclone
// serialises into its own buffers there. The sample's arrays are sized at
// open(), so write() itself allocates nothing.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "joint_channels.hpp"
#include "topic_sink.hpp"

namespace sinew::hal::dds {

struct JointStateSinkOptions {
  uint32_t domain_id = 0;     // ROS_DOMAIN_ID's meaning; 0..232
  std::string ros_namespace;  // "" or "/": the root
  std::string topic = "joint_states";
  std::string frame_id;  // header.frame_id
  uint32_t depth = 10;   // history, keep-last
  // header.stamp = the frame's timestamp + this (ns): the daemon passes the
  // offset from its clock to CLOCK_REALTIME, ROS 2's time.
  int64_t stamp_offset_ns = 0;
};

class JointStateSink : public TopicSink {
 public:
  JointStateSink();
  ~JointStateSink() override;

  // channels: one per frame input, in order. False with `error` (the
  // topic's name, Cyclone's message) when the participant, topic or writer
  // cannot be created.
  bool open(const JointStateSinkOptions& options, std::span<const JointChannel> channels, int32_t length_exponent,
            std::string* error);

  bool write(const PoseFrame& frame) override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace sinew::hal::dds
