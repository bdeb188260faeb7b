// The DDS [[source]] and [[sink]] types (hal/dds; docs/ros2.md): the rig's
// inputs as ROS 2's sensor_msgs/msg/JointState, out and in. Their keys and
// registry entries are in sources.cpp and sinks.cpp. In a build without
// Cyclone DDS (the board cross builds) both refuse with that reason.
#pragma once

#include <memory>
#include <string>

#include "hal/common/input_source.hpp"
#include "hal/common/output_sink.hpp"
#include "sinks.hpp"
#include "sources.hpp"

namespace sinew::firmware {

// Whether this sinewd was built with Cyclone DDS.
bool dds_available();

std::unique_ptr<hal::InputSource> open_dds_source(const SourceConfig& s, const SourceSetup& setup, std::string* error);
// The JointState writer itself, unqueued (sinks.cpp queues it).
std::unique_ptr<hal::OutputSink> open_dds_joint_state_sink(const SinkConfig& s, const SinkSetup& setup,
                                                           std::string* error);
// The skin as a Marker, unqueued; null with an empty *error when the table
// turns it off (mesh_rate_hz = 0 or mesh_topic = ""), with a message on error.
// *every_n_frames: the decimation from the tick rate to mesh_rate_hz.
// sinew's own frame (tick, input health bits, stage times), unqueued; null
// with an empty *error when frame_topic = "".
std::unique_ptr<hal::OutputSink> open_dds_frame_sink(const SinkConfig& s, const SinkSetup& setup, std::string* error);
std::unique_ptr<hal::OutputSink> open_dds_mesh_sink(const SinkConfig& s, const SinkSetup& setup,
                                                    uint64_t* every_n_frames, std::string* error);

}  // namespace sinew::firmware
