// ROS 2's names on DDS: topics "rt/<namespace>/<topic>", the JointState
// type as rosidl names it, and names ROS 2 would refuse refused.
#include "hal/dds/ros2_names.hpp"

#include <gtest/gtest.h>

namespace ros2_names_test {

using sinew::hal::dds::ros2_topic_name;

std::string topic(std::string_view ns, std::string_view name) {
  std::string out, error;
  EXPECT_TRUE(ros2_topic_name(ns, name, &out, &error)) << error;
  return out;
}

TEST(Ros2Names, TopicsAreRtThenTheFullyQualifiedName) {
  EXPECT_EQ(topic("", "joint_states"), "rt/joint_states");
  EXPECT_EQ(topic("/", "joint_states"), "rt/joint_states");
  EXPECT_EQ(topic("board_a", "joint_states"), "rt/board_a/joint_states");
  EXPECT_EQ(topic("/left_glove", "joint_states"), "rt/left_glove/joint_states");
  EXPECT_EQ(topic("/robot/arm_1", "joint_states"), "rt/robot/arm_1/joint_states");
  EXPECT_EQ(topic("", "sinew/joint_states"), "rt/sinew/joint_states");
}

TEST(Ros2Names, NamesRos2RefusesAreRefused) {
  std::string out, error;
  for (const char* ns : {"1board", "board-a", "a//b", "a/", "a b", "ä"}) {
    EXPECT_FALSE(ros2_topic_name(ns, "joint_states", &out, &error)) << ns;
    EXPECT_NE(error.find("namespace"), std::string::npos) << error;
  }
  for (const char* t : {"", "/joint_states", "joint states", "2d", "joint_states/", "a//b"}) {
    EXPECT_FALSE(ros2_topic_name("", t, &out, &error)) << t;
    EXPECT_NE(error.find("topic"), std::string::npos) << error;
  }
}

// The type on the wire must be ROS 2's exactly, or rmw_cyclonedds_cpp's
// readers and writers never match sinew's.
TEST(Ros2Names, TheRegisteredTypeIsRos2sJointState) {
  EXPECT_EQ(sinew::hal::dds::kJointStateTypeName, "sensor_msgs::msg::dds_::JointState_");
  EXPECT_EQ(sinew::hal::dds::registered_joint_state_type_name(), sinew::hal::dds::kJointStateTypeName);
}

}  // namespace ros2_names_test
