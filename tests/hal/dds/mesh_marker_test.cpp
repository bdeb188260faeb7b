// The skin as a ROS 2 Marker: a TRIANGLE_LIST whose points are the frame's
// vertices in metres, three a triangle, in the configured frame; read back
// by a plain DDS reader of the ROS 2 type, as RViz's Marker display would.
#include <dds/dds.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <chrono>
#include <thread>

#include "hal/dds/mesh_marker_sink.hpp"
#include "hal/dds/ros2_names.hpp"
#include "hal/units/float_to_fixed.hpp"
#include "visualization_msgs/msg/Marker.h"

namespace mesh_marker_test {

using namespace sinew::hal;

TEST(MeshMarker, TheRegisteredTypeIsRos2sMarker) {
  EXPECT_EQ(dds::kMarkerTypeName, "visualization_msgs::msg::dds_::Marker_");
  EXPECT_EQ(dds::registered_marker_type_name(), dds::kMarkerTypeName);
}

TEST(MeshMarker, ATriangleNamingAMissingVertexIsRefused) {
  dds::MeshMarkerSink sink;
  const uint32_t triangles[] = {0, 1, 4};
  std::string error;
  EXPECT_FALSE(sink.open({}, triangles, 4, &error));
  EXPECT_NE(error.find("vertex 4 of 4"), std::string::npos) << error;
}

TEST(MeshMarker, TrianglesArriveAsPointsInMetres) {
  const std::string ns = "t" + std::to_string(getpid()) + "_mesh";
  dds::MeshMarkerSinkOptions o;
  o.ros_namespace = ns;
  o.frame_id = "arm_base";
  const uint32_t triangles[] = {0, 1, 2, 2, 1, 3};
  dds::MeshMarkerSink sink;
  std::string error;
  ASSERT_TRUE(sink.open(o, triangles, 4, &error)) << error;

  const dds_entity_t participant = dds_create_participant(DDS_DOMAIN_DEFAULT, nullptr, nullptr);
  const std::string name = "rt/" + ns + "/skin";
  const dds_entity_t topic =
      dds_create_topic(participant, &visualization_msgs_msg_dds__Marker__desc, name.c_str(), nullptr, nullptr);
  dds_qos_t* qos = dds_create_qos();
  dds_qset_reliability(qos, DDS_RELIABILITY_BEST_EFFORT, 0);
  const dds_entity_t reader = dds_create_reader(participant, topic, qos, nullptr);
  dds_delete_qos(qos);
  ASSERT_GT(reader, 0);

  const int32_t x[4] = {0, 1 << 20, 0, -(3 << 19)}, y[4] = {0, 0, 1 << 20, 5}, z[4] = {7, 8, 9, 10};
  PoseFrame frame;
  frame.timestamp_ns = 1'500'000'000;
  frame.length_exponent = -4;
  frame.vertex_count = 4;
  frame.position[0] = x;
  frame.position[1] = y;
  frame.position[2] = z;
  void* samples[1] = {nullptr};
  dds_sample_info_t info;
  int taken = 0;
  // Best effort: write until one arrives (loopback loses none in practice).
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(30);
  while (taken <= 0 && std::chrono::steady_clock::now() < deadline) {
    if (sink.matched_readers() > 0) {
      ASSERT_TRUE(sink.write(frame));
    }
    std::this_thread::sleep_for(std::chrono::milliseconds(5));
    samples[0] = nullptr;
    taken = dds_take(reader, samples, &info, 1, 1);
    if (taken > 0 && !info.valid_data) {
      dds_return_loan(reader, samples, taken);
      taken = 0;
    }
  }
  ASSERT_GT(taken, 0);
  const auto& m = *static_cast<const visualization_msgs_msg_dds__Marker_*>(samples[0]);
  EXPECT_EQ(m.type, 11);  // TRIANGLE_LIST
  EXPECT_EQ(m.action, 0);
  EXPECT_STREQ(m.header.frame_id, "arm_base");
  EXPECT_EQ(m.header.stamp.sec, 1);
  EXPECT_EQ(m.header.stamp.nanosec, 500'000'000u);
  EXPECT_DOUBLE_EQ(m.pose.orientation.w, 1.0);
  ASSERT_EQ(m.points._length, 6u);
  for (uint32_t i = 0; i < 6; ++i) {
    const uint32_t v = triangles[i];
    EXPECT_EQ(m.points._buffer[i].x, sinew::units::len_to_double(x[v], -4)) << i;
    EXPECT_EQ(m.points._buffer[i].y, sinew::units::len_to_double(y[v], -4)) << i;
    EXPECT_EQ(m.points._buffer[i].z, sinew::units::len_to_double(z[v], -4)) << i;
  }
  EXPECT_DOUBLE_EQ(m.points._buffer[1].x, 1.0 / 16);  // one rig unit of 2^-4 m
  dds_return_loan(reader, samples, taken);
  dds_delete(participant);
}

}  // namespace mesh_marker_test
