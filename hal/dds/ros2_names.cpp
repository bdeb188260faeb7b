#include "ros2_names.hpp"

#include <algorithm>

#include "sensor_msgs/msg/JointState.h"
#include "sinew/msg/Frame.h"
#include "visualization_msgs/msg/Marker.h"

namespace sinew::hal::dds {

namespace {

bool valid_tokens(std::string_view path) {
  if (path.empty()) return false;
  size_t begin = 0;
  while (begin <= path.size()) {
    const size_t end = std::min(path.find('/', begin), path.size());
    const std::string_view token = path.substr(begin, end - begin);
    if (token.empty()) return false;  // "//" or a trailing '/'
    const char first = token.front();
    if (!(first == '_' || (first >= 'A' && first <= 'Z') || (first >= 'a' && first <= 'z'))) return false;
    for (const char c : token)
      if (!(c == '_' || (c >= 'A' && c <= 'Z') || (c >= 'a' && c <= 'z') || (c >= '0' && c <= '9'))) return false;
    begin = end + 1;
  }
  return true;
}

}  // namespace

bool ros2_topic_name(std::string_view ros_namespace, std::string_view topic, std::string* dds_topic,
                     std::string* error) {
  if (!ros_namespace.empty() && ros_namespace.front() == '/') ros_namespace.remove_prefix(1);
  if (!ros_namespace.empty() && !valid_tokens(ros_namespace))
    return *error = "namespace '" + std::string(ros_namespace) +
                    "': ROS 2 names are tokens of letters, digits and '_' (not starting with a digit) separated by "
                    "single '/'",
           false;
  if (!valid_tokens(topic))
    return *error = "topic '" + std::string(topic) +
                    "': a relative ROS 2 name (tokens of letters, digits and '_', not starting with a digit, "
                    "separated by single '/')",
           false;
  *dds_topic = "rt/" + (ros_namespace.empty() ? std::string() : std::string(ros_namespace) + "/") + std::string(topic);
  return true;
}

std::string_view registered_joint_state_type_name() { return sensor_msgs_msg_dds__JointState__desc.m_typename; }
std::string_view registered_marker_type_name() { return visualization_msgs_msg_dds__Marker__desc.m_typename; }
std::string_view registered_frame_type_name() { return sinew_msg_dds__Frame__desc.m_typename; }

}  // namespace sinew::hal::dds
