#include "mesh_marker_sink.hpp"

#include <dds/dds.h>

#include <vector>

#include "dds_writer.hpp"
#include "hal/units/float_to_fixed.hpp"
#include "qos.hpp"
#include "visualization_msgs/msg/Marker.h"

namespace sinew::hal::dds {

namespace {
constexpr int32_t kTriangleList = 11;  // visualization_msgs/Marker TRIANGLE_LIST
constexpr int32_t kAdd = 0;            // ADD (and MODIFY)
}  // namespace

struct MeshMarkerSink::Impl {
  std::vector<uint32_t> triangles;
  uint32_t vertex_count = 0;
  int64_t stamp_offset_ns = 0;
  std::string frame_id, marker_ns;
  std::vector<geometry_msgs_msg_dds__Point_> points;
  visualization_msgs_msg_dds__Marker_ sample{};
  char empty[1] = {0};
};

MeshMarkerSink::MeshMarkerSink()
    : TopicSink("dds-mesh", "visualization_msgs/msg/Marker"), impl_(std::make_unique<Impl>()) {}
MeshMarkerSink::~MeshMarkerSink() = default;

bool MeshMarkerSink::open(const MeshMarkerSinkOptions& options, std::span<const uint32_t> triangles,
                          uint32_t vertex_count, std::string* error) {
  if (triangles.size() % 3 != 0) return *error = "the triangle list is not 3 indices a triangle", false;
  for (const uint32_t v : triangles)
    if (v >= vertex_count)
      return *error = "a triangle names vertex " + std::to_string(v) + " of " + std::to_string(vertex_count), false;
  Impl& s = *impl_;
  if (!writer().open(options.domain_id, options.ros_namespace, options.topic, &visualization_msgs_msg_dds__Marker__desc,
                     mesh_qos(), error))
    return false;

  s.triangles.assign(triangles.begin(), triangles.end());
  s.vertex_count = vertex_count;
  s.stamp_offset_ns = options.stamp_offset_ns;
  s.frame_id = options.frame_id;
  s.marker_ns = options.marker_ns;
  s.points.assign(triangles.size(), geometry_msgs_msg_dds__Point_{0, 0, 0});
  visualization_msgs_msg_dds__Marker_& m = s.sample;
  m = {};
  m.header.frame_id = s.frame_id.data();
  m.ns = s.marker_ns.data();
  m.id = 0;
  m.type = kTriangleList;
  m.action = kAdd;
  m.pose.orientation.w = 1;  // the points are in the frame itself
  m.scale = {1, 1, 1};       // TRIANGLE_LIST scales the points by it
  m.color = {options.color[0], options.color[1], options.color[2], options.color[3]};
  m.frame_locked = false;
  const auto count = static_cast<uint32_t>(s.points.size());
  m.points = {count, count, s.points.data(), false};
  m.texture_resource = s.empty;
  m.texture.header.frame_id = s.empty;
  m.texture.format = s.empty;
  m.text = s.empty;
  m.mesh_resource = s.empty;
  m.mesh_file.filename = s.empty;
  set_type("visualization_msgs/msg/Marker, " + std::to_string(s.triangles.size() / 3) + " triangles");
  return true;
}

bool MeshMarkerSink::write(const PoseFrame& frame) {
  Impl& s = *impl_;
  if (!writer().valid() || frame.vertex_count != s.vertex_count || frame.position[0] == nullptr) return reject();
  for (size_t i = 0; i < s.triangles.size(); ++i) {
    const uint32_t v = s.triangles[i];
    s.points[i] = {units::len_to_double(frame.position[0][v], frame.length_exponent),
                   units::len_to_double(frame.position[1][v], frame.length_exponent),
                   units::len_to_double(frame.position[2][v], frame.length_exponent)};
  }
  const Ros2Time stamp = ros2_time(static_cast<int64_t>(frame.timestamp_ns) + s.stamp_offset_ns);
  s.sample.header.stamp = {stamp.sec, stamp.nanosec};
  return publish(&s.sample);
}

}  // namespace sinew::hal::dds
