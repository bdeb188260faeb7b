// ROS 2's names on DDS (the ROS 2 design article "Topic and Service name
// mapping to DDS", as rmw_cyclonedds_cpp applies it): a ROS topic /ns/topic
// is the DDS topic "rt/ns/topic", and a message pkg/msg/Type is the DDS type
// "pkg::msg::dds_::Type_". Names are checked as ROS 2 checks them (rcl's
// validate_topic_name), so a name ROS 2 would refuse is refused here too.
#pragma once

#include <string>
#include <string_view>

namespace sinew::hal::dds {

inline constexpr std::string_view kJointStateTypeName = "sensor_msgs::msg::dds_::JointState_";

// The type name the JointState topic is registered with: the one idlc
// generated from idl/sensor_msgs/msg/JointState.idl (a test holds it to
// kJointStateTypeName, the name ROS 2 gives the type on DDS).
std::string_view registered_joint_state_type_name();

inline constexpr std::string_view kMarkerTypeName = "visualization_msgs::msg::dds_::Marker_";
std::string_view registered_marker_type_name();

inline constexpr std::string_view kFrameTypeName = "sinew::msg::dds_::Frame_";
std::string_view registered_frame_type_name();

// The DDS topic of ROS topic `topic` in namespace `ros_namespace` ("" or "/"
// for the root; with or without a leading '/'): "rt/<namespace>/<topic>".
// Tokens are [A-Za-z_][A-Za-z0-9_]*, separated by single '/'. False with
// `error` naming what is wrong.
bool ros2_topic_name(std::string_view ros_namespace, std::string_view topic, std::string* dds_topic,
                     std::string* error);

}  // namespace sinew::hal::dds
