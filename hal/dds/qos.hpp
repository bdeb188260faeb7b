// The QoS of sinew's DDS topics (docs/ros2.md, "QoS"). Private to hal/dds:
// it names Cyclone's types.
#pragma once

#include <dds/dds.h>

#include <cstdint>

namespace sinew::hal::dds {

// ROS 2's domain ids stop at 232 (the RTPS port arithmetic's limit).
inline constexpr uint32_t kMaxDomainId = 232;

// JointState, both ends: ROS 2's default profile (rmw_qos_profile_default):
// reliable, keep-last `depth`, volatile. A reliable writer blocks at most
// 100 ms on a full reader history before its write fails.
inline dds_qos_t* joint_state_qos(uint32_t depth) {
  dds_qos_t* qos = dds_create_qos();
  dds_qset_reliability(qos, DDS_RELIABILITY_RELIABLE, DDS_MSECS(100));
  dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, static_cast<int32_t>(depth));
  dds_qset_durability(qos, DDS_DURABILITY_VOLATILE);
  return qos;
}

// The mesh (Marker): best effort, keep-last 1, volatile: a mesh that is late
// is replaced by the next, never retransmitted or queued (RViz's Marker
// display subscribes reliably by default; set it to best effort, or it
// matches nothing: docs/ros2.md).
inline dds_qos_t* mesh_qos() {
  dds_qos_t* qos = dds_create_qos();
  dds_qset_reliability(qos, DDS_RELIABILITY_BEST_EFFORT, 0);
  dds_qset_history(qos, DDS_HISTORY_KEEP_LAST, 1);
  dds_qset_durability(qos, DDS_DURABILITY_VOLATILE);
  return qos;
}

}  // namespace sinew::hal::dds
