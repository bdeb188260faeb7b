// The deformed skin as ROS 2's visualization_msgs/msg/Marker on DDS
// (docs/ros2.md): a TRIANGLE_LIST in metres, three points a triangle, in the
// frame the configuration names, so RViz shows the live skin with its Marker
// display and no plugin. Best effort, keep-last 1, volatile: a late or lost
// mesh is replaced by the next one, never queued.
//
// write() runs on the sink's I/O thread; the points are sized at open(), so
// write() itself allocates nothing.
#pragma once

#include <cstdint>
#include <memory>
#include <span>
#include <string>

#include "topic_sink.hpp"

namespace sinew::hal::dds {

struct MeshMarkerSinkOptions {
  uint32_t domain_id = 0;
  std::string ros_namespace;
  std::string topic = "skin";
  std::string frame_id = "sinew";   // header.frame_id: the rig's model frame
  std::string marker_ns = "sinew";  // Marker.ns (with id 0: one marker, replaced each time)
  float color[4] = {0.87f, 0.70f, 0.60f, 1.0f};
  int64_t stamp_offset_ns = 0;  // as JointStateSinkOptions::stamp_offset_ns
};

class MeshMarkerSink : public TopicSink {
 public:
  MeshMarkerSink();
  ~MeshMarkerSink() override;

  // triangles: 3 vertex indices a triangle, each < vertex_count. False with
  // `error` for an index out of range or a DDS entity that cannot be made.
  bool open(const MeshMarkerSinkOptions& options, std::span<const uint32_t> triangles, uint32_t vertex_count,
            std::string* error);

  // A frame with another vertex count than open()'s is refused (counted).
  bool write(const PoseFrame& frame) override;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace sinew::hal::dds
