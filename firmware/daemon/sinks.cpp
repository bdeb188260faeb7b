#include "sinks.hpp"

#include <cstdio>

#include "dds_endpoints.hpp"
#include "firmware/runtime/async_sink.hpp"
#include "firmware/runtime/recording.hpp"
#include "firmware/sinks/decimating_sink.hpp"
#include "firmware/sinks/fan_out_sink.hpp"
#include "firmware/sinks/inputs_only_sink.hpp"
#include "hal/can/candump_frame_writer.hpp"
#include "hal/can/socketcan_writer.hpp"
#include "hal/output/can_pose_sink.hpp"
#include "hal/output/frame_log_writer.hpp"
#include "hal/output/udp_sender.hpp"

namespace sinew::firmware {
namespace {

// Every sink writes from its own I/O thread through a ring of frames of
// `dims`; one frame in `every_n_frames` enters it.
std::unique_ptr<OutputSink> queued(const DaemonConfig& config, std::unique_ptr<OutputSink> sink, const FrameDims& dims,
                                   uint64_t every_n_frames = 1) {
  AsyncSinkOptions options;
  options.ring_frames = static_cast<size_t>(config.realtime.sink_ring_frames);
  options.lossless = config.mode != RunMode::kLive;  // no deadline: wait rather than lose frames
  options.fifo_priority = config.mode == RunMode::kLive ? config.realtime.io_fifo_priority : 0;
  options.cpu = config.mode == RunMode::kLive ? config.realtime.io_cpu : -1;
  options.poll_ns = config.mode == RunMode::kLive ? static_cast<uint64_t>(config.realtime.io_poll_us) * 1000u : 0;
  std::string report;
  std::unique_ptr<OutputSink> q = std::make_unique<AsyncSink>(std::move(sink), dims, options, &report);
  if (!report.empty()) std::printf("%s", report.c_str());
  // Decimation in the tick thread: the frames left out never enter the ring.
  if (every_n_frames > 1) q = std::make_unique<DecimatingSink>(std::move(q), every_n_frames);
  return q;
}

// The frame every sink of this rig receives; normals when the table asks
// for them and the rig has them.
hal::output::FrameShape frame_shape(const SinkConfig& s, const LoadedRig& rig) {
  hal::output::FrameShape shape;
  shape.vertex_count = rig.rig.vertex_count();
  shape.input_count = rig.input_count();
  shape.length_exponent = rig.rig.length_exponent;
  shape.normals = s.table["normals"].value_or(false) && !rig.rig.normal[0].empty();
  return shape;
}

FrameDims frame_dims(const LoadedRig& rig) {
  return {rig.rig.vertex_count(), rig.input_count(), !rig.rig.normal[0].empty()};
}

std::unique_ptr<OutputSink> failed(const SinkConfig& s, std::string* error) {
  *error = "sink " + s.name + ": " + *error;
  return nullptr;
}

constexpr std::string_view kCompressions[] = {"none", "zstd"};

constexpr ConfigKey kLogKeys[] = {{"type", KeyKind::kString},
                                  {"name", KeyKind::kString},
                                  {"normals", KeyKind::kFlag},
                                  {"path", KeyKind::kString},
                                  {"sync_every_frames", KeyKind::kInteger, 0, 1e9},
                                  {"every_n_frames", KeyKind::kInteger, 1, 1e6},
                                  {"compression", KeyKind::kChoice, 0, 0, {}, kCompressions},
                                  {"compression_level", KeyKind::kInteger, 1, 19},
                                  {"key_every_frames", KeyKind::kInteger, 1, 1e9}};

// A frame log of every tick's pose (hal/output/frame_log_writer.hpp).
std::unique_ptr<OutputSink> open_log(const SinkConfig& s, const SinkSetup& setup, std::string* error) {
  const auto path = s.table["path"].value<std::string>();
  if (!path) return *error = "path is required", failed(s, error);
  hal::output::FrameLogOptions options;
  options.sync_every_frames = s.table["sync_every_frames"].value_or(0u);
  options.compress = s.table["compression"].value_or<std::string>("none") == "zstd";
  options.compression_level = s.table["compression_level"].value_or(options.compression_level);
  options.key_every_frames = s.table["key_every_frames"].value_or(options.key_every_frames);
  auto log = std::make_unique<hal::output::FrameLogWriter>();
  if (!log->open(*path, frame_shape(s, setup.rig), options, error)) return failed(s, error);
  log->set_name(s.name);
  return queued(setup.config, std::move(log), frame_dims(setup.rig), s.table["every_n_frames"].value_or(uint64_t{1}));
}

constexpr ConfigKey kRecordKeys[] = {{"type", KeyKind::kString},
                                     {"name", KeyKind::kString},
                                     {"path", KeyKind::kString},
                                     {"sync_every_frames", KeyKind::kInteger, 0, 1e9}};

// The inputs as applied each tick, and the run they drove: enough for
// `sinew-log render` to regenerate every frame (recording.hpp).
std::unique_ptr<OutputSink> open_record(const SinkConfig& s, const SinkSetup& setup, std::string* error) {
  const auto path = s.table["path"].value<std::string>();
  if (!path) return *error = "path is required", failed(s, error);
  RunDescription run;
  run.rig_xxh64 = rig_blob_hash(setup.rig.blob.data(), setup.rig.blob.size);
  run.rig_bytes = setup.rig.blob.size;
  run.options = setup.options;
  hal::output::FrameShape inputs_only = frame_shape(s, setup.rig);
  inputs_only.vertex_count = 0;
  inputs_only.normals = false;
  hal::output::FrameLogOptions options;
  options.sync_every_frames = s.table["sync_every_frames"].value_or(0u);
  options.metadata = encode_run_description(run);
  auto log = std::make_unique<hal::output::FrameLogWriter>();
  if (!log->open(*path, inputs_only, options, error)) return failed(s, error);
  log->set_name(s.name);
  // The vertices are left out before the ring: its slots hold inputs only.
  const FrameDims inputs_dims{0, setup.rig.input_count(), false};
  return std::make_unique<RecordingSink>(queued(setup.config, std::move(log), inputs_dims));
}

constexpr ConfigKey kUdpKeys[] = {{"type", KeyKind::kString},
                                  {"name", KeyKind::kString},
                                  {"normals", KeyKind::kFlag},
                                  {"host", KeyKind::kString},
                                  {"port", KeyKind::kInteger, 1, kMaxPort},
                                  {"max_datagram_bytes", KeyKind::kInteger, 41, 65507}};

// The pose stream over UDP (hal/output/udp_sender.hpp, docs/frame-formats.md).
std::unique_ptr<OutputSink> open_udp(const SinkConfig& s, const SinkSetup& setup, std::string* error) {
  const std::string host = s.table["host"].value_or<std::string>("127.0.0.1");
  const int64_t port = s.table["port"].value_or(int64_t{0});
  if (port <= 0 || port > 65535) return *error = "port must be 1..65535", failed(s, error);
  hal::output::UdpSenderOptions options;
  options.max_datagram_bytes = s.table["max_datagram_bytes"].value_or(options.max_datagram_bytes);
  auto udp = std::make_unique<hal::output::UdpSender>();
  if (!udp->open(host, static_cast<uint16_t>(port), frame_shape(s, setup.rig), options, error)) return failed(s, error);
  udp->set_name(s.name);
  return queued(setup.config, std::move(udp), frame_dims(setup.rig));
}

constexpr std::string_view kCanProtocols[] = {"joint-stream", "joint-frames"};

constexpr ConfigKey kCanKeys[] = {{"type", KeyKind::kString},
                                  {"name", KeyKind::kString},
                                  {"interface", KeyKind::kString},
                                  {"candump", KeyKind::kString},
                                  {"protocol", KeyKind::kChoice, 0, 0, {}, kCanProtocols},
                                  {"fd", KeyKind::kFlag},
                                  {"can_id", KeyKind::kInteger, 0, 0x1FFFFFFF},
                                  {"extended_id", KeyKind::kFlag}};

// The applied inputs on a CAN bus every tick (hal/output/can_pose_sink.hpp):
// in the joint-stream protocol sinew's CAN sources read
// (docs/can-protocol.md; `fd` packs eight inputs a frame), or as compact
// joint frames on one identifier (`protocol = "joint-frames"`, `can_id`,
// `extended_id`; docs/frame-formats.md). On a SocketCAN `interface`, or,
// with `candump` (a path), into a candump log as the simulated twin;
// `interface` then names the bus in its lines.
std::unique_ptr<OutputSink> open_can(const SinkConfig& s, const SinkSetup& setup, std::string* error) {
  const auto interface = s.table["interface"].value<std::string>();
  const auto candump = s.table["candump"].value<std::string>();
  std::unique_ptr<hal::can::FrameWriter> writer;
  if (candump) {
    auto log = std::make_unique<hal::can::CandumpFrameWriter>();
    if (!log->open(*candump, interface.value_or("can0"), error)) return failed(s, error);
    writer = std::move(log);
  } else if (interface) {
    hal::can::SocketCanWriterOptions options;
    options.interface = *interface;
    auto bus = std::make_unique<hal::can::SocketCanWriter>(options);
    if (!bus->open(error)) return failed(s, error);
    writer = std::move(bus);
  } else {
    return *error = "interface (a SocketCAN interface) or candump (a log path) is required", failed(s, error);
  }
  hal::output::CanPoseSinkOptions options;
  if (s.table["protocol"].value_or<std::string>("joint-stream") == "joint-frames")
    options.protocol = hal::output::CanOutputProtocol::kJointFrames;
  options.fd = s.table["fd"].value_or(false);
  options.period_ns = setup.config.rate_hz > 0 ? 1'000'000'000u / setup.config.rate_hz : 0;
  options.frames.can_id = s.table["can_id"].value_or(options.frames.can_id);
  options.frames.extended_id = s.table["extended_id"].value_or(false);
  auto can = std::make_unique<hal::output::CanPoseSink>();
  if (!can->open(options, setup.rig.input_count(), std::move(writer), error)) return failed(s, error);
  can->set_name(s.name);
  // Inputs only in the ring: the CAN frames carry no vertices.
  const FrameDims inputs_dims{0, setup.rig.input_count(), false};
  return std::make_unique<InputsOnlySink>(queued(setup.config, std::move(can), inputs_dims), "");
}

constexpr ConfigKey kDdsKeys[] = {{"type", KeyKind::kString},
                                  {"name", KeyKind::kString},
                                  {"domain_id", KeyKind::kInteger, 0, 232},
                                  {"namespace", KeyKind::kString},
                                  {"topic", KeyKind::kString},
                                  {"frame_id", KeyKind::kString},
                                  {"depth", KeyKind::kInteger, 1, 1000},
                                  {"mesh_topic", KeyKind::kString},
                                  {"mesh_rate_hz", KeyKind::kNumber, 0, 1000},
                                  {"mesh_frame_id", KeyKind::kString},
                                  {"frame_topic", KeyKind::kString}};

// The applied inputs as ROS 2's sensor_msgs/msg/JointState on DDS every tick,
// sinew's own frame (sinew/msg/Frame) every tick, and the skin as a
// visualization_msgs/msg/Marker at mesh_rate_hz
// (dds_endpoints.hpp, docs/ros2.md), each from its own I/O thread.
std::unique_ptr<OutputSink> open_dds(const SinkConfig& s, const SinkSetup& setup, std::string* error) {
  std::unique_ptr<OutputSink> joints = open_dds_joint_state_sink(s, setup, error);
  if (!joints) return nullptr;
  std::vector<std::unique_ptr<OutputSink>> outputs;
  const FrameDims inputs_dims{0, setup.rig.input_count(), false};
  outputs.push_back(std::make_unique<InputsOnlySink>(queued(setup.config, std::move(joints), inputs_dims), ""));
  std::unique_ptr<OutputSink> own = open_dds_frame_sink(s, setup, error);
  if (!own && !error->empty()) return nullptr;
  const FrameDims status_dims{0, setup.rig.input_count(), false, pipeline::kStageCount};
  if (own) outputs.push_back(std::make_unique<InputsOnlySink>(queued(setup.config, std::move(own), status_dims), ""));
  uint64_t every_n = 1;
  std::unique_ptr<OutputSink> mesh = open_dds_mesh_sink(s, setup, &every_n, error);
  if (!mesh && !error->empty()) return nullptr;
  if (mesh) outputs.push_back(queued(setup.config, std::move(mesh), frame_dims(setup.rig), every_n));
  return std::make_unique<FanOutSink>(s.name, std::move(outputs));
}

constexpr SinkType kSinkTypes[] = {
    {"log", kLogKeys, open_log}, {"record", kRecordKeys, open_record}, {"udp", kUdpKeys, open_udp},
    {"can", kCanKeys, open_can}, {"dds", kDdsKeys, open_dds},
};

}  // namespace

std::span<const SinkType> sink_types() { return kSinkTypes; }

bool add_sinks(const DaemonConfig& config, const LoadedRig& rig, Runtime* runtime, std::string* error) {
  const SinkSetup setup{config, rig, runtime->pipeline().options};
  for (const SinkConfig& s : config.sinks) {
    const SinkType* type = nullptr;
    for (const SinkType& t : kSinkTypes)
      if (t.type == s.type) type = &t;
    if (type == nullptr) {
      std::string known;
      for (const SinkType& t : kSinkTypes) known += (known.empty() ? "" : ", ") + std::string(t.type);
      return *error = "sink " + s.name + ": unknown type '" + s.type + "' (" + known + ")", false;
    }
    std::unique_ptr<OutputSink> sink = type->open(s, setup, error);
    if (!sink) return false;
    runtime->add_sink(std::move(sink));
  }
  return true;
}

}  // namespace sinew::firmware
