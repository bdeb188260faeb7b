// Joint angles in from ROS 2's sensor_msgs/msg/JointState on DDS
// (docs/ros2.md): another board's sinewd, a ROS 2 robot's joint_states, or a
// host merging several boards. A reader thread takes the samples, checks
// them and hands the latest value of each joint to the tick through a
// triple buffer, so latch() never blocks, never allocates and never calls
// DDS (as ModbusSource does with its poller).
//
// A sample is taken whole or rejected whole, and counted: its arrays must
// have one entry per name (position always; velocity and effort one per
// name or none), every configured joint must be among its names (others
// are ignored), and each value must be finite and convert to the engine's
// range. Staleness and holding are the runtime's, as for every source.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <span>
#include <string>
#include <thread>
#include <vector>

#include "hal/common/input_source.hpp"
#include "hal/common/triple_buffer.hpp"
#include "joint_channels.hpp"

namespace sinew::hal::dds {

struct JointStateSourceOptions {
  std::string name = "dds";
  uint32_t domain_id = 0;
  std::string ros_namespace;  // "" or "/": the root
  std::string topic = "joint_states";
  uint32_t depth = 10;
  int32_t length_exponent = 0;  // of the rig the values feed
  struct Joint {
    JointChannel channel;  // the name on the JointState and its unit (kNewton: read from effort)
    uint16_t input = 0;    // the rig input it feeds
  };
  std::vector<Joint> joints;
};

// Cumulative counts, readable from any thread.
struct JointStateSourceCounters {
  uint64_t samples = 0;           // taken with data
  uint64_t accepted = 0;          // taken whole
  uint64_t rejected_lengths = 0;  // arrays not one entry per name
  uint64_t rejected_names = 0;    // a configured joint missing
  uint64_t rejected_values = 0;   // non-finite or beyond the engine's range
  uint32_t publishers = 0;        // matched now
};

class JointStateSource : public InputSource {
 public:
  // Creates the participant, topic and reader and starts the reader thread.
  // Null with `error` naming the topic and Cyclone's message.
  static std::unique_ptr<JointStateSource> create(JointStateSourceOptions options, std::string* error);
  ~JointStateSource() override;

  const char* name() const override { return options_.name.c_str(); }
  size_t latch(uint64_t until_ns, std::span<JointSample> out, InputHealth& health) override;
  // down: no publisher matched (none yet, or it went away); ok otherwise.
  SourceState state() const override;
  std::string status_line() const override;

  JointStateSourceCounters counters() const;
  const std::string& dds_topic() const { return dds_topic_; }

 private:
  struct Dds;
  // What the reader thread hands the tick: per joint its latest value, when
  // it was taken (CLOCK_MONOTONIC) and how many were accepted so far.
  struct Latest {
    std::vector<int32_t> value;
    std::vector<uint64_t> taken_ns;
    std::vector<uint64_t> accepted;
    uint64_t rejected = 0;  // samples rejected whole, so far
  };

  explicit JointStateSource(JointStateSourceOptions options);
  void run();
  void take(const void* sample, uint64_t now_ns);

  JointStateSourceOptions options_;
  std::string dds_topic_;
  std::unique_ptr<Dds> dds_;
  Latest current_;  // reader thread only
  TripleBuffer<Latest> exchange_;
  std::vector<uint64_t> latched_;  // tick only: accepted counts already handed out
  uint64_t latched_rejected_ = 0;
  std::atomic<uint64_t> samples_{0}, accepted_{0}, rejected_lengths_{0}, rejected_names_{0}, rejected_values_{0};
  std::atomic<uint32_t> publishers_{0};
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

}  // namespace sinew::hal::dds
