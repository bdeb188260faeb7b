// What every DDS sink shares: one writer of one ROS 2 topic (its
// participant, topic and writer: dds_writer.hpp), its name in reports, the
// samples it wrote and failed to write, the readers matched now, and its
// status line. Each sink (JointStateSink, MeshMarkerSink, FrameSink) opens
// the writer with its type and QoS, fills its sample from a frame and
// publishes it.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

#include "hal/common/output_sink.hpp"

namespace sinew::hal::dds {

class DdsWriter;

class TopicSink : public OutputSink {
 public:
  ~TopicSink() override;
  TopicSink(const TopicSink&) = delete;
  TopicSink& operator=(const TopicSink&) = delete;

  void set_name(std::string name) { name_ = std::move(name); }
  const char* name() const override { return name_.c_str(); }
  void flush() override {}
  // "dds rt/<ns>/<topic> (<type>): N written, M failed, K readers matched".
  std::string status_line() const override;

  // rt/<namespace>/<topic> once open; empty before.
  const std::string& dds_topic() const;
  uint64_t written() const { return written_; }
  uint64_t failed() const { return failed_; }
  // Readers matched now (any thread).
  uint32_t matched_readers() const;

 protected:
  // name: the sink's name in reports until set_name; type: the message type
  // the status line names.
  TopicSink(std::string name, std::string type);
  DdsWriter& writer() { return *writer_; }
  void set_type(std::string type) { type_ = std::move(type); }
  // Writes the sample filled for this frame and counts it.
  bool publish(const void* sample);
  // A frame the sink cannot publish (not open, wrong shape): counted.
  bool reject() {
    ++failed_;
    return false;
  }

 private:
  std::unique_ptr<DdsWriter> writer_;
  std::string name_, type_;
  uint64_t written_ = 0, failed_ = 0;
};

}  // namespace sinew::hal::dds
