#include "dds_endpoints.hpp"

#include <time.h>

#include <algorithm>
#include <cstdio>
#include <vector>

#if SINEW_HAVE_DDS
#include "hal/dds/frame_sink.hpp"
#include "hal/dds/joint_state_sink.hpp"
#include "hal/dds/joint_state_source.hpp"
#include "hal/dds/mesh_marker_sink.hpp"
#include "sim_core/pipeline/stage_table.hpp"
#endif

namespace sinew::firmware {

#if SINEW_HAVE_DDS

namespace {

// Every input of the rig as a JointState joint: its name, and rad or m by
// its DOF's kind; external inputs in N (forces) or their own unit.
std::vector<hal::dds::JointChannel> rig_channels(const LoadedRig& rig) {
  std::vector<hal::dds::JointChannel> channels(rig.input_count());
  for (size_t k = 0; k < channels.size(); ++k) channels[k].name = rig.input_names[k];
  for (const rig::JointRecord& j : rig.rig.joints)
    for (uint32_t d = 0; d < j.dof_count; ++d)
      channels[j.first_input + d].unit = j.dof_kind == static_cast<uint8_t>(rig::DofKind::kRotation)
                                             ? hal::dds::JointUnit::kRadian
                                             : hal::dds::JointUnit::kMetre;
  for (size_t k = 0; k < rig.external.size(); ++k)
    channels[rig.rig.input_count + k].unit =
        rig.external[k].force ? hal::dds::JointUnit::kNewton : hal::dds::JointUnit::kScalar;
  return channels;
}

int64_t ns_of(const timespec& t) { return int64_t{t.tv_sec} * 1'000'000'000 + t.tv_nsec; }

// header.stamp is ROS 2 time (CLOCK_REALTIME): a live frame's monotonic
// time moved by the clocks' offset now; an offline or replay frame's time,
// counted from 0, from now.
int64_t stamp_offset_ns(bool live) {
  timespec real{}, mono{};
  clock_gettime(CLOCK_REALTIME, &real);
  clock_gettime(CLOCK_MONOTONIC, &mono);
  return live ? ns_of(real) - ns_of(mono) : ns_of(real);
}

}  // namespace

bool dds_available() { return true; }

std::unique_ptr<hal::InputSource> open_dds_source(const SourceConfig& s, const SourceSetup& setup, std::string* error) {
  hal::dds::JointStateSourceOptions o;
  o.name = s.name;
  o.domain_id = s.table["domain_id"].value_or(0u);
  o.ros_namespace = s.table["namespace"].value_or<std::string>("");
  o.topic = s.table["topic"].value_or<std::string>("joint_states");
  o.depth = s.table["depth"].value_or(10u);
  o.length_exponent = setup.rig.rig.length_exponent;
  const std::vector<hal::dds::JointChannel> channels = rig_channels(setup.rig);
  if (const toml::array* joints = s.table["joint"].as_array()) {
    // [[source.joint]] name = "<JointState name>", input = "<rig input>".
    for (const toml::node& n : *joints) {
      const toml::table& t = *n.as_table();
      uint16_t input = 0;
      if (!read_input(s, t, setup.rig, "joint", &input, error)) return nullptr;
      const auto name = t["name"].value<std::string>();
      if (!name || name->empty())
        return *error = "source " + s.name + ": joint.name is required (the joint's name on the JointState)", nullptr;
      o.joints.push_back({{*name, channels[input].unit}, input});
    }
  } else {
    // Without a table: every rig input, by its own name (a board of the same rig).
    for (size_t k = 0; k < channels.size(); ++k) o.joints.push_back({channels[k], static_cast<uint16_t>(k)});
  }
  auto source = hal::dds::JointStateSource::create(std::move(o), error);
  if (!source) *error = "source " + s.name + ": " + *error;
  return source;
}

std::unique_ptr<hal::OutputSink> open_dds_joint_state_sink(const SinkConfig& s, const SinkSetup& setup,
                                                           std::string* error) {
  hal::dds::JointStateSinkOptions o;
  o.domain_id = s.table["domain_id"].value_or(0u);
  o.ros_namespace = s.table["namespace"].value_or<std::string>("");
  o.topic = s.table["topic"].value_or<std::string>("joint_states");
  o.frame_id = s.table["frame_id"].value_or<std::string>("");
  o.depth = s.table["depth"].value_or(10u);
  o.stamp_offset_ns = stamp_offset_ns(setup.config.mode == RunMode::kLive);
  auto sink = std::make_unique<hal::dds::JointStateSink>();
  if (!sink->open(o, rig_channels(setup.rig), setup.rig.rig.length_exponent, error)) {
    *error = "sink " + s.name + ": " + *error;
    return nullptr;
  }
  sink->set_name(s.name);
  std::printf("sinewd: sink %s publishes sensor_msgs/msg/JointState on DDS topic %s (domain %u)\n", s.name.c_str(),
              sink->dds_topic().c_str(), o.domain_id);
  return sink;
}

std::unique_ptr<hal::OutputSink> open_dds_frame_sink(const SinkConfig& s, const SinkSetup& setup, std::string* error) {
  error->clear();
  hal::dds::FrameSinkOptions o;
  o.topic = s.table["frame_topic"].value_or<std::string>("sinew_frame");
  if (o.topic.empty()) return nullptr;
  o.domain_id = s.table["domain_id"].value_or(0u);
  o.ros_namespace = s.table["namespace"].value_or<std::string>("");
  o.frame_id = s.table["frame_id"].value_or<std::string>("");
  o.depth = s.table["depth"].value_or(10u);
  o.stamp_offset_ns = stamp_offset_ns(setup.config.mode == RunMode::kLive);
  std::vector<std::string> stages;
  for (const pipeline::StageInfo& info : pipeline::kStages) stages.emplace_back(info.name);
  auto sink = std::make_unique<hal::dds::FrameSink>();
  if (!sink->open(o, setup.rig.input_names, stages, error)) {
    *error = "sink " + s.name + ": " + *error;
    return nullptr;
  }
  sink->set_name(s.name);
  std::printf("sinewd: sink %s publishes sinew/msg/Frame (tick, input health, stage times) on DDS topic %s\n",
              s.name.c_str(), sink->dds_topic().c_str());
  return sink;
}

std::unique_ptr<hal::OutputSink> open_dds_mesh_sink(const SinkConfig& s, const SinkSetup& setup,
                                                    uint64_t* every_n_frames, std::string* error) {
  error->clear();
  const double mesh_hz = s.table["mesh_rate_hz"].value_or(30.0);
  hal::dds::MeshMarkerSinkOptions o;
  o.topic = s.table["mesh_topic"].value_or<std::string>("skin");
  if (mesh_hz <= 0 || o.topic.empty()) return nullptr;
  o.domain_id = s.table["domain_id"].value_or(0u);
  o.ros_namespace = s.table["namespace"].value_or<std::string>("");
  o.frame_id = s.table["mesh_frame_id"].value_or<std::string>("sinew");
  o.stamp_offset_ns = stamp_offset_ns(setup.config.mode == RunMode::kLive);
  // The nearest whole number of ticks per mesh, at least one.
  *every_n_frames = std::max<uint64_t>(1, static_cast<uint64_t>(setup.config.rate_hz / mesh_hz + 0.5));
  auto sink = std::make_unique<hal::dds::MeshMarkerSink>();
  if (!sink->open(o, setup.rig.rig.triangles, setup.rig.rig.vertex_count(), error)) {
    *error = "sink " + s.name + ": " + *error;
    return nullptr;
  }
  sink->set_name(s.name);
  std::printf(
      "sinewd: sink %s publishes visualization_msgs/msg/Marker (the skin, %zu triangles) on DDS topic %s "
      "every %llu ticks\n",
      s.name.c_str(), setup.rig.rig.triangles.size() / 3, sink->dds_topic().c_str(),
      static_cast<unsigned long long>(*every_n_frames));
  return sink;
}

#else

namespace {
const char* const kNoDds =
    ": this sinewd was built without Cyclone DDS (install cyclonedds-dev and cyclonedds-tools, then rebuild)";
}  // namespace

bool dds_available() { return false; }

std::unique_ptr<hal::InputSource> open_dds_source(const SourceConfig& s, const SourceSetup&, std::string* error) {
  return *error = "source " + s.name + kNoDds, nullptr;
}

std::unique_ptr<hal::OutputSink> open_dds_joint_state_sink(const SinkConfig& s, const SinkSetup&, std::string* error) {
  return *error = "sink " + s.name + kNoDds, nullptr;
}

std::unique_ptr<hal::OutputSink> open_dds_mesh_sink(const SinkConfig& s, const SinkSetup&, uint64_t*,
                                                    std::string* error) {
  return *error = "sink " + s.name + kNoDds, nullptr;
}

std::unique_ptr<hal::OutputSink> open_dds_frame_sink(const SinkConfig& s, const SinkSetup&, std::string* error) {
  return *error = "sink " + s.name + kNoDds, nullptr;
}

#endif

}  // namespace sinew::firmware
