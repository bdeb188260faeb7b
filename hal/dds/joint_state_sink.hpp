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

#include "hal/common/output_sink.hpp"
#include "joint_channels.hpp"

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

class JointStateSink : public OutputSink {
 public:
  JointStateSink();
  ~JointStateSink() override;

  // channels: one per frame input, in order. False with `error` (the
  // topic's name, Cyclone's message) when the participant, topic or writer
  // cannot be created.
  bool open(const JointStateSinkOptions& options, std::span<const JointChannel> channels, int32_t length_exponent,
            std::string* error);
  void set_name(std::string name) { name_ = std::move(name); }

  const char* name() const override { return name_.c_str(); }
  bool write(const PoseFrame& frame) override;
  void flush() override {}
  std::string status_line() const override;

  const std::string& dds_topic() const { return dds_topic_; }
  uint64_t written() const { return written_; }
  // Readers matched now (any thread).
  uint32_t matched_readers() const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
  std::string name_ = "dds";
  std::string dds_topic_;
  uint64_t written_ = 0, failed_ = 0;
};

}  // namespace sinew::hal::dds
