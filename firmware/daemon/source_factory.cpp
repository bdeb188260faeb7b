#include "source_factory.hpp"

#include <cmath>
#include <cstdio>

#include "bus_sources.hpp"
#include "firmware/runtime/async_sink.hpp"
#include "firmware/runtime/recording.hpp"
#include "firmware/sinks/decimating_sink.hpp"
#include "firmware/sinks/hal_sink.hpp"
#include "firmware/sources/trajectory_source.hpp"
#include "hal/output/frame_log_writer.hpp"
#include "hal/output/udp_sender.hpp"

namespace sinew::firmware {

std::vector<InputLimits> input_limits(const LoadedRig& rig, const DaemonConfig& config, uint64_t) {
  std::vector<InputLimits> limits(rig.input_count());
  const auto timeout = static_cast<uint64_t>(config.timeout_factor * config.default_period_ms * 1e6);
  const int64_t margin_angle = static_cast<int64_t>(config.range_margin_deg / 360.0 * 4294967296.0);
  for (const rig::JointRecord& j : rig.rig.joints) {
    for (uint32_t d = 0; d < j.dof_count; ++d) {
      InputLimits& l = limits[j.first_input + d];
      const int64_t span = int64_t{j.dof_max[d]} - j.dof_min[d];
      const int64_t margin = j.dof_kind == static_cast<uint8_t>(rig::DofKind::kRotation) ? margin_angle : span / 10;
      l.min = static_cast<int32_t>(std::max<int64_t>(INT32_MIN, j.dof_min[d] - margin));
      l.max = static_cast<int32_t>(std::min<int64_t>(INT32_MAX, j.dof_max[d] + margin));
      l.timeout_ns = timeout;
    }
  }
  for (size_t k = 0; k < rig.external.size(); ++k) {
    const ExternalInput& e = rig.external[k];
    InputLimits& l = limits[rig.rig.input_count + k];
    const int64_t margin = (int64_t{e.max} - e.min) / 10;
    l.min = static_cast<int32_t>(std::max<int64_t>(INT32_MIN, e.min - margin));
    l.max = static_cast<int32_t>(std::min<int64_t>(INT32_MAX, e.max + margin));
    l.timeout_ns = timeout;
  }
  return limits;
}

bool add_sources(const DaemonConfig& config, const LoadedRig& rig, uint64_t, uint64_t start_ns, Runtime* runtime,
                 std::string* error) {
  for (const SourceConfig& s : config.sources) {
    if (s.type == "trajectory") {
      const double period_ms = s.table["period_ms"].value_or(config.default_period_ms);
      // Below 10 us or beyond a minute the tick-count arithmetic would overflow or divide by zero.
      if (!(period_ms >= 0.01 && period_ms <= 60000))
        return *error = "source " + s.name + ": period_ms must be in [0.01, 60000]", false;
      std::vector<int32_t> min(rig.rig.input_count, 0), max(rig.rig.input_count, 0);
      for (const rig::JointRecord& j : rig.rig.joints)
        for (uint32_t d = 0; d < j.dof_count; ++d) {
          min[j.first_input + d] = j.dof_min[d];
          max[j.first_input + d] = j.dof_max[d];
        }
      runtime->add_source(std::make_unique<TrajectorySource>(std::move(min), std::move(max),
                                                             static_cast<uint64_t>(period_ms * 1e6), start_ns));
    } else {
      std::unique_ptr<hal::InputSource> source = make_bus_source(s, rig, config, start_ns, error);
      if (!source) return false;
      runtime->add_source(std::move(source));
    }
  }
  return true;
}

bool layer_options(const DaemonConfig& config, const LoadedRig& rig, pipeline::PipelineOptions* out,
                   std::string* error) {
  const pipeline::LayerSet& l = rig.layers;
  struct Switch {
    bool on, compiled;
    const char* key;
    const char* table;
  };
  const Switch switches[] = {{config.layer_sph, l.sph_count > 0, "sph", "[[sph]]"},
                             {config.layer_metaballs, l.has_metaballs, "metaballs", "[metaballs]"},
                             {config.layer_barnet, l.barnet_count > 0, "barnet", "[[barnet]]"},
                             {config.layer_anatomy, l.has_muscles, "anatomy", "[[muscle]] and [skin]"}};
  for (const Switch& s : switches)
    if (s.on && !s.compiled)
      return *error = std::string("[layers] ") + s.key +
                      " = true, but the rig carries no such layer (compile it with " + s.table +
                      " in the rig's spec; this rig has: " + describe_layers(rig) + ")",
             false;
  pipeline::PipelineOptions o;
  o.sph = config.layer_sph;
  o.metaballs = config.layer_metaballs;
  o.barnet = config.layer_barnet;
  o.anatomy = config.layer_anatomy;
  o.tresca = config.layer_tresca;
  o.sph_joint_measured = config.layer_sph_joint_measured;
  o.skin_iterations = static_cast<uint32_t>(config.layer_skin_iterations);
  o.skin_max_anchor_acceleration = static_cast<uint32_t>(config.layer_skin_max_anchor_acceleration);
  o.tick_hz = config.rate_hz;
  *out = o;
  return true;
}

void print_layer_costs(const Runtime& runtime) {
  const StageTimes& t = runtime.stage_times();
  if (t.ticks == 0) return;
  uint64_t total = 0;
  for (uint64_t ns : t.total_ns) total += ns;
  std::printf("  tick by stage (mean, share, max):");
  for (uint32_t s = 0; s < pipeline::kStageCount; ++s) {
    if (!pipeline::pipeline_stage_on(runtime.pipeline(), static_cast<pipeline::Stage>(s))) continue;
    std::printf(" %s %.1f us %.0f%% %.1f us;", pipeline::stage_name(static_cast<pipeline::Stage>(s)),
                static_cast<double>(t.total_ns[s]) / static_cast<double>(t.ticks) / 1000.0,
                total > 0 ? 100.0 * static_cast<double>(t.total_ns[s]) / static_cast<double>(total) : 0.0,
                static_cast<double>(t.max_ns[s]) / 1000.0);
  }
  std::printf("\n");
}

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

}  // namespace

bool add_sinks(const DaemonConfig& config, const LoadedRig& rig, Runtime* runtime, std::string* error) {
  hal::output::FrameShape shape;
  shape.vertex_count = rig.rig.vertex_count();
  shape.input_count = rig.input_count();
  shape.length_exponent = rig.rig.length_exponent;
  const FrameDims dims{rig.rig.vertex_count(), rig.input_count(), !rig.rig.normal[0].empty()};
  for (const SinkConfig& s : config.sinks) {
    const bool normals = s.table["normals"].value_or(false);
    shape.normals = normals && !rig.rig.normal[0].empty();
    if (s.type == "log") {
      const auto path = s.table["path"].value<std::string>();
      if (!path) return *error = "sink " + s.name + ": path is required", false;
      hal::output::FrameLogOptions options;
      options.sync_every_frames = s.table["sync_every_frames"].value_or(0u);
      options.compress = s.table["compression"].value_or<std::string>("none") == "zstd";
      options.compression_level = s.table["compression_level"].value_or(options.compression_level);
      options.key_every_frames = s.table["key_every_frames"].value_or(options.key_every_frames);
      auto log = std::make_unique<hal::output::FrameLogWriter>();
      if (!log->open(*path, shape, options, error)) return *error = "sink " + s.name + ": " + *error, false;
      runtime->add_sink(queued(config, std::make_unique<HalSink<hal::output::FrameLogWriter>>(std::move(log), s.name),
                               dims, s.table["every_n_frames"].value_or(uint64_t{1})));
    } else if (s.type == "record") {
      // The inputs as applied each tick, and the run they drove: enough for
      // `sinew-log render` to regenerate every frame (recording.hpp).
      const auto path = s.table["path"].value<std::string>();
      if (!path) return *error = "sink " + s.name + ": path is required", false;
      RunDescription run;
      run.rig_xxh64 = rig_blob_hash(rig.blob.data(), rig.blob.size);
      run.rig_bytes = rig.blob.size;
      run.options = runtime->pipeline().options;
      hal::output::FrameShape inputs_only = shape;
      inputs_only.vertex_count = 0;
      inputs_only.normals = false;
      hal::output::FrameLogOptions options;
      options.sync_every_frames = s.table["sync_every_frames"].value_or(0u);
      options.metadata = encode_run_description(run);
      auto log = std::make_unique<hal::output::FrameLogWriter>();
      if (!log->open(*path, inputs_only, options, error)) return *error = "sink " + s.name + ": " + *error, false;
      // The vertices are left out before the ring: its slots hold inputs only.
      const FrameDims inputs_dims{0, dims.input_count, false};
      runtime->add_sink(std::make_unique<RecordingSink>(
          queued(config, std::make_unique<HalSink<hal::output::FrameLogWriter>>(std::move(log), s.name), inputs_dims)));
    } else if (s.type == "udp") {
      const std::string host = s.table["host"].value_or<std::string>("127.0.0.1");
      const int64_t port = s.table["port"].value_or(int64_t{0});
      if (port <= 0 || port > 65535) return *error = "sink " + s.name + ": port must be 1..65535", false;
      hal::output::UdpSenderOptions options;
      options.max_datagram_bytes = s.table["max_datagram_bytes"].value_or(options.max_datagram_bytes);
      auto udp = std::make_unique<hal::output::UdpSender>();
      if (!udp->open(host, static_cast<uint16_t>(port), shape, options, error))
        return *error = "sink " + s.name + ": " + *error, false;
      runtime->add_sink(
          queued(config, std::make_unique<HalSink<hal::output::UdpSender>>(std::move(udp), s.name), dims));
    } else {
      return *error = "sink " + s.name + ": unknown type '" + s.type + "' (log, record, udp)", false;
    }
  }
  return true;
}

void print_stats(Runtime& runtime, const LoadedRig& rig, bool final_report) {
  StepTiming& t = runtime.timing();
  const InputHealth& h = runtime.health();
  uint64_t rejected = 0, accepted = 0;
  for (size_t i = 0; i < rig.input_count(); ++i) {
    accepted += h.counters(i).accepted;
    for (uint64_t r : h.counters(i).rejected) rejected += r;
  }
  for (uint64_t r : h.unassigned().rejected) rejected += r;
  std::printf(
      "%s tick %llu: step p50 %.1f us p99 %.1f us max %.1f us, deadline misses %llu, inputs stale %zu/%u, "
      "samples accepted %llu rejected %llu, frames dropped %llu\n",
      final_report ? "final" : "stats", static_cast<unsigned long long>(runtime.ticks()),
      static_cast<double>(t.percentile_ns(0.5)) / 1000.0, static_cast<double>(t.percentile_ns(0.99)) / 1000.0,
      static_cast<double>(t.max_ns()) / 1000.0, static_cast<unsigned long long>(t.deadline_misses()), h.stale_count(),
      rig.input_count(), static_cast<unsigned long long>(accepted), static_cast<unsigned long long>(rejected),
      static_cast<unsigned long long>(runtime.dropped_frames()));
  for (const auto& s : runtime.sources())
    std::printf("  source %-10s %-8s %s\n", s->name(), source_state_name(s->state()), s->status_line().c_str());
  print_layer_costs(runtime);
  if (runtime.layer_errors() > 0)
    std::printf("  layer errors %llu (the last: %s)\n", static_cast<unsigned long long>(runtime.layer_errors()),
                runtime.last_layer_error());
  for (const auto& s : runtime.sinks()) std::printf("  sink   %-10s %s\n", s->name(), s->status_line().c_str());
  if (final_report) {
    // Per-reason totals, one line the tests (and log scrapers) can parse.
    uint64_t by_reason[static_cast<int>(hal::RejectReason::kCount)] = {};
    uint64_t stale_events = 0;
    for (size_t i = 0; i < rig.input_count(); ++i) {
      for (int r = 0; r < static_cast<int>(hal::RejectReason::kCount); ++r) by_reason[r] += h.counters(i).rejected[r];
      stale_events += h.counters(i).stale_events;
    }
    std::printf("  rejected by reason:");
    for (int r = 0; r < static_cast<int>(hal::RejectReason::kCount); ++r)
      std::printf(" %s %llu", hal::reject_reason_name(static_cast<hal::RejectReason>(r)),
                  static_cast<unsigned long long>(by_reason[r] + h.unassigned().rejected[r]));
    std::printf("; stale events %llu\n", static_cast<unsigned long long>(stale_events));
  }
  if (final_report && h.stale_count() > 0) {
    for (size_t i = 0; i < rig.input_count(); ++i)
      if (h.status()[i] & hal::kJointStale) std::printf("  stale input %s\n", rig.input_names[i].c_str());
  }
  std::fflush(stdout);
}

}  // namespace sinew::firmware
