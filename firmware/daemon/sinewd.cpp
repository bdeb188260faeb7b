// sinewd: the runtime daemon. Reads a TOML config, loads the rig, opens the
// configured sources and sinks, and runs the fixed-rate tick until its
// duration ends or SIGINT/SIGTERM arrives; then flushes outputs and prints
// the final report.
//   sinewd --config FILE [--duration S] [--offline]
#include <CLI/CLI.hpp>
#include <atomic>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <exception>

#include "config.hpp"
#include "config_registry.hpp"
#include "firmware/rig/loaded_rig.hpp"
#include "firmware/runtime/cpu_latency.hpp"
#include "firmware/runtime/privileges.hpp"
#include "firmware/runtime/runtime.hpp"
#include "firmware/runtime/tick_clock.hpp"
#include "firmware/runtime/tick_trigger.hpp"
#include "firmware/runtime/worker_pool.hpp"
#include "run_setup.hpp"
#include "service_notify.hpp"
#include "sim_core/pipeline/stage_table.hpp"
#include "sinks.hpp"
#include "sources.hpp"
#include "stats_report.hpp"
#include "status_publisher.hpp"
#include "step_fit.hpp"

namespace {

std::atomic<bool> g_stop{false};
extern "C" void on_signal(int) { g_stop.store(true); }

// The longest --duration accepted, the same as [loop] duration_s's maximum
// (about 115 days): beyond it the tick count is no longer exact.
constexpr double kMaxDurationS = 1e7;

// A duration in seconds: finite, not negative, at most kMaxDurationS.
bool parse_duration(const std::string& text, double* out) {
  errno = 0;
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || end != text.c_str() + text.size() || errno == ERANGE || !std::isfinite(v) || v < 0 ||
      v > kMaxDurationS)
    return false;
  *out = v;
  return true;
}

// --check-config: everything sinewd checks before it opens a device, file
// or socket: the file's keys, types and ranges (every [[source]] and
// [[sink]] against its type's keys), the rig, the layers it switches on and
// the pipeline's acceptance of them at the configured rate.
int check_config(const std::string& path) {
  using namespace sinew::firmware;
  DaemonConfig config;
  std::string error;
  LoadedRig rig;
  sinew::pipeline::PipelineOptions options;
  if (!load_config(path, &config, &error) || !load_rig(config.rig_builtin, config.rig_blob, &rig, &error) ||
      !layer_options(config, rig, &options, &error) || !pipeline_accepts(rig, options, &error)) {
    std::fprintf(stderr, "sinewd: %s\n", error.c_str());
    return 2;
  }
  std::printf("# %s: valid (sinewd --check-config); every key resolved\n%s", path.c_str(),
              resolved_config_text(config).c_str());
  return 0;
}

int run(int argc, char** argv) {
  using namespace sinew::firmware;
  CLI::App app{"sinewd: joint angles in, deformed pose out, at a fixed rate"};
  std::string config_path;
  std::string duration_text;
  bool offline = false;
  std::string check_path;
  bool print_defaults = false;
  auto* config_option = app.add_option("--config", config_path, "TOML configuration");
  app.add_option("--duration", duration_text, "seconds to run (overrides [loop] duration_s; 0 = until signalled)");
  app.add_flag("--offline", offline, "re-simulate as fast as possible on nominal tick times");
  auto* check_option = app.add_option(
      "--check-config", check_path,
      "parse and validate a configuration (rig, layers, sources' and sinks' keys), print it with every default "
      "filled in, and exit: 0 if it is valid, 2 with file:line:key if not; opens no device, file or socket");
  auto* defaults_flag =
      app.add_flag("--print-default-config", print_defaults, "print every key with its default and exit");
  config_option->excludes(check_option)->excludes(defaults_flag);
  check_option->excludes(defaults_flag);
  CLI11_PARSE(app, argc, argv);
  if (print_defaults) {
    std::printf("%s", default_config_text().c_str());
    return 0;
  }
  if (!check_path.empty()) return check_config(check_path);
  if (config_path.empty()) {
    std::fprintf(stderr, "sinewd: --config FILE is required (or --check-config FILE, --print-default-config)\n");
    return 2;
  }
  double duration = -1;
  if (app.count("--duration") > 0 && !parse_duration(duration_text, &duration)) {
    std::fprintf(stderr, "sinewd: --duration '%s': must be a number of seconds in [0, %g]\n", duration_text.c_str(),
                 kMaxDurationS);
    return 2;
  }

  DaemonConfig config;
  std::string error;
  if (!load_config(config_path, &config, &error)) {
    std::fprintf(stderr, "sinewd: %s\n", error.c_str());
    return 2;
  }
  if (duration >= 0) config.duration_s = duration;
  // A user the daemon cannot become is refused before anything is opened.
  if (!config.realtime.user.empty() && !can_drop_privileges(config.realtime.user, &error)) {
    std::fprintf(stderr, "sinewd: %s\n", error.c_str());
    return 2;
  }
  if (offline) config.mode = RunMode::kOffline;
  LoadedRig rig;
  if (!load_rig(config.rig_builtin, config.rig_blob, &rig, &error)) {
    std::fprintf(stderr, "sinewd: %s\n", error.c_str());
    return 2;
  }
  // The workers outlive the runtime, whose pipeline holds them.
  WorkerPool workers;
  Runtime runtime;
  sinew::pipeline::PipelineOptions options;
  if (!layer_options(config, rig, &options, &error)) {
    std::fprintf(stderr, "sinewd: %s\n", error.c_str());
    return 2;
  }
  const bool live = config.mode == RunMode::kLive;
  std::string worker_report;
  if (!workers.start(static_cast<uint32_t>(resolved_workers(config.realtime.workers)),
                     live ? config.realtime.fifo_priority : 0, live ? config.realtime.worker_cpu : -1, &worker_report,
                     &error)) {
    std::fprintf(stderr, "sinewd: %s\n", error.c_str());
    return 2;
  }
  options.workers = workers.workers();
  const std::vector<InputLimits> limits = input_limits(rig, config, 1000000000u / config.rate_hz);
  // The CPUs' wake-up latency is requested first, so the probe below
  // measures the machine the run will see.
  CpuLatencyRequest cpu_latency;
  const std::string latency_report =
      live && config.realtime.cpu_latency_us >= 0 ? cpu_latency.request(config.realtime.cpu_latency_us) : std::string();
  // A live run first times its own step on this machine ([loop] step_budget,
  // over_budget): it may warn, refuse, or run at a slower rate that fits.
  StepFit fit{config.rate_hz, config.rate_hz, {}};
  if (live && config.step_budget > 0 && !fit_step_to_budget(&config, rig, limits, &options, &fit, &error)) {
    std::printf("%s", fit.report.c_str());
    std::fprintf(stderr, "sinewd: %s\n", error.c_str());
    return 2;
  }
  const uint64_t period = 1000000000u / config.rate_hz;
  // Live ticks start 50 ms from now: opening sources and sinks must not make
  // the first tick late (a late tick is skipped, not burst).
  const uint64_t start = live ? monotonic_ns() + 50000000u : 0;
  if (!runtime.init(rig.rig, rig.layers, options, limits, start, &error) ||
      !add_sources(config, rig, start, &runtime, &error) || !add_sinks(config, rig, &runtime, &error)) {
    std::fprintf(stderr, "sinewd: %s\n", error.c_str());
    return 2;
  }
  const std::unique_ptr<StatusPublisher> status = StatusPublisher::create(config, runtime, &error);
  if (!status && !error.empty()) {
    std::fprintf(stderr, "sinewd: %s\n", error.c_str());
    return 2;
  }
  if (status) {
    std::printf("sinewd: status registers on Modbus TCP %s:%u\n", config.status.modbus_bind.c_str(),
                static_cast<unsigned>(status->port()));
    std::fflush(stdout);
  }
  if (config.mode == RunMode::kLive && config.trigger != TickTrigger::kPeriodic) {
    // A trigger no source can pull would leave every tick to its deadline.
    bool signalled = false;
    for (const auto& s : runtime.sources()) signalled |= (s->arrival_signals() & trigger_signal(config.trigger)) != 0;
    if (!signalled) {
      std::fprintf(stderr, "sinewd: [loop] trigger = \"%s\": no source %s (%s)\n", tick_trigger_name(config.trigger),
                   config.trigger == TickTrigger::kInputs ? "reports complete sample sets" : "has a sync frame",
                   config.trigger == TickTrigger::kInputs
                       ? "can, candump, simulated-rig, trajectory"
                       : "set sync_id on a can, candump or simulated-rig source, or a gpio [source.sync] line");
      return 2;
    }
  }
  std::printf("sinewd: rig %s, %u joints, %u inputs (%zu external), %u vertices; %u Hz, mode %s, trigger %s\n",
              config.rig_builtin.empty() ? config.rig_blob.c_str() : config.rig_builtin.c_str(), rig.rig.joint_count(),
              rig.input_count(), rig.external.size(), rig.rig.vertex_count(), config.rate_hz,
              config.mode == RunMode::kLive ? "live" : (config.mode == RunMode::kReplay ? "replay" : "offline"),
              config.mode == RunMode::kLive ? tick_trigger_name(config.trigger) : "nominal times");
  std::printf("%s", fit.report.c_str());
  if (!rig.unused_inputs.empty()) {
    std::string names;
    for (uint32_t k : rig.unused_inputs) names += (names.empty() ? "" : ", ") + rig.input_names[k];
    std::printf("sinewd: note: rig inputs that drive no joint (read and logged only): %s\n", names.c_str());
  }
  if (config.mode == RunMode::kLive) {
    const std::string rt = latency_report + apply_realtime(config.realtime);
    if (!rt.empty()) std::printf("%s", rt.c_str());
  }
  std::string parallel;
  for (const sinew::pipeline::StageInfo& s : sinew::pipeline::kStages)
    if (s.parallel && options.stages.has(s.stage) && s.compiled(rig.layers) > 0) parallel += std::string(" ") + s.name;
  std::printf("sinewd: workers %u (the tick thread and %u more) for:%s\n%s", workers.threads(), workers.threads() - 1,
              parallel.empty() ? " no stage that runs" : parallel.c_str(), worker_report.c_str());
  std::string layers;
  for (const sinew::pipeline::StageInfo& s : sinew::pipeline::kStages)
    if (s.stage != sinew::pipeline::Stage::kSkinning && options.stages.has(s.stage) && s.compiled(rig.layers) > 0)
      layers += std::string(" ") + s.name;
  std::printf("sinewd: layers in the rig: %s; running: %s\n", describe_layers(rig).c_str(),
              layers.empty() ? "skinning only" : layers.c_str() + 1);
  if (!config.realtime.user.empty()) {
    std::string report;
    if (!drop_privileges(config.realtime.user, &report, &error)) {
      std::fprintf(stderr, "sinewd: %s\n", error.c_str());
      return 2;
    }
    std::printf("%s", report.c_str());
  }
  std::signal(SIGINT, on_signal);
  std::signal(SIGTERM, on_signal);
  // Under systemd (Type=notify): ready now that the sources and sinks are
  // open; the watchdog is kicked only by completed ticks.
  ServiceNotifier service;
  if (service.watchdog_interval_ns() != 0)
    std::printf("sinewd: systemd watchdog: WATCHDOG=1 after completed ticks, at most every %llu ms\n",
                static_cast<unsigned long long>(service.watchdog_interval_ns() / 2000000u));
  service.ready("running: " + std::to_string(config.rate_hz) + " Hz");

  const uint64_t total_ticks =
      config.duration_s > 0 ? static_cast<uint64_t>(config.duration_s * config.rate_hz) : UINT64_MAX;
  const uint64_t stats_every =
      config.stats_interval_s > 0
          ? std::max<uint64_t>(1, static_cast<uint64_t>(config.stats_interval_s * config.rate_hz))
          : UINT64_MAX;
  TickClock clock(period, start + period);
  // [loop] trigger: a live tick may start before its deadline, as soon as
  // its inputs (or a sync frame) have arrived; the deadline stays the fallback.
  const bool triggered = live && config.trigger != TickTrigger::kPeriodic;
  MonotonicWaitClock wall;
  TriggeredTickClock trigger_clock(config.trigger, period, start + period,
                                   static_cast<uint64_t>(config.trigger_poll_us * 1000.0));
  // The run lasts duration_s of schedule: it ends at the slot, not after a
  // count of executed ticks (a live run that skipped ticks would run long).
  uint64_t on_arrival = 0, at_deadline = 0;
  for (uint64_t tick = 0; !g_stop.load(std::memory_order_relaxed); ++tick) {
    uint64_t tick_ns = start + (tick + 1) * period, deadline = tick_ns;
    bool arrived = false;
    if (triggered) {
      const TriggeredTick t = trigger_clock.wait_next(runtime.sources(), wall);
      tick_ns = t.time_ns;
      deadline = t.deadline_ns;
      arrived = t.triggered;
    } else if (live) {
      tick_ns = deadline = clock.wait_next();
    }
    const uint64_t slot = (deadline - start) / period - 1;
    if (slot >= total_ticks) break;
    ++(arrived ? on_arrival : at_deadline);
    const uint64_t t0 = monotonic_ns();
    const sinew::hal::PoseFrame& frame = runtime.step(tick_ns, slot);
    const uint64_t t1 = monotonic_ns();
    if (status) status->publish(runtime, frame, t1 - t0);
    runtime.timing().record(t1 - t0, live && (triggered ? trigger_clock.finished_late(t1) : clock.finished_late(t1)));
    service.tick_completed(t1);
    if ((tick + 1) % stats_every == 0) service.status(print_stats(runtime, rig, false));
  }
  service.stopping();
  const uint64_t lost_frames = runtime.close_sinks();  // writes what the sinks' queues hold
  print_stats(runtime, rig, true);
  if (status) std::printf("  %s\n", status->status_line().c_str());
  const uint64_t skipped = clock.skipped_ticks() + trigger_clock.skipped_ticks();
  if (skipped > 0)
    std::printf("skipped ticks (more than a period late): %llu\n", static_cast<unsigned long long>(skipped));
  if (live) std::printf("%s\n", run_verdict(runtime, skipped, fit.rate_hz, fit.configured_hz).c_str());
  if (triggered)
    std::printf("trigger %s: %llu ticks on arrival, %llu at the deadline (fallback)\n",
                tick_trigger_name(config.trigger), static_cast<unsigned long long>(on_arrival),
                static_cast<unsigned long long>(at_deadline));
  if (lost_frames > 0) {
    // A sink that lost frames (a full disk, a failing link, a full queue)
    // left an incomplete output.
    std::printf("sinewd: %llu frames dropped by the sinks: the output is incomplete\n",
                static_cast<unsigned long long>(lost_frames));
    return 1;
  }
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  // Whatever escapes (a bad allocation, a library's exception) ends the
  // daemon with a message and the configuration-error status, not abort().
  try {
    return run(argc, argv);
  } catch (const std::exception& e) {
    std::fprintf(stderr, "sinewd: %s\n", e.what());
  } catch (...) {
    std::fprintf(stderr, "sinewd: unexpected error\n");
  }
  return 2;
}
