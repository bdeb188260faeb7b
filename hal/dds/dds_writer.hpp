// One DDS writer of a ROS 2 topic with its participant and topic: what the
// dds sinks share (private to hal/dds: it names Cyclone's types). Also ROS
// 2's time from a sinew timestamp.
#pragma once

#include <dds/dds.h>

#include <cstdint>
#include <string>

#include "dds_entity.hpp"

namespace sinew::hal::dds {

class DdsWriter {
 public:
  // The participant on `domain_id`, the topic rt/<ros_namespace>/<topic> of
  // `type`, and a writer with `qos` (taken over: deleted here). False with
  // `error` naming the entity that failed and Cyclone's message.
  bool open(uint32_t domain_id, const std::string& ros_namespace, const std::string& topic,
            const dds_topic_descriptor_t* type, dds_qos_t* qos, std::string* error);
  bool valid() const { return writer_.valid(); }
  bool write(const void* sample) const { return writer_.valid() && dds_write(writer_.get(), sample) == DDS_RETCODE_OK; }
  uint32_t matched_readers() const;
  const std::string& dds_topic() const { return dds_topic_; }

 private:
  DdsEntity participant_, topic_, writer_;
  std::string dds_topic_;
};

// builtin_interfaces/Time of `ns` (floor seconds, nanoseconds in [0, 1e9)).
struct Ros2Time {
  int32_t sec;
  uint32_t nanosec;
};
Ros2Time ros2_time(int64_t ns);

}  // namespace sinew::hal::dds
