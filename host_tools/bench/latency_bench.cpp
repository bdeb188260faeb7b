// End-to-end latency of the runtime at 1 kHz on the built-in rigs: a joint
// frame arrives on the (simulated) CAN bus, waits for the next tick, is
// decoded, the engine steps and the pose frame leaves to a sink. Ticks run
// back to back on virtual 1 ms deadlines so the figures are the work itself:
//   step      wall time of one tick (latch + decode + health + engine + sink)
//   latency   (tick time - frame arrival) + step time, per accepted frame:
//             what a frame waits for its tick plus the work that turns it
//             into an outgoing pose
// The baseline is the engine step alone on the same rig (no IO), in the
// same run; the ratio is the runtime's overhead.
//
// Then arrival to output in real time: the same rig and bus paced on the
// wall clock at 1 kHz, twice in the same run: periodic ticks (a frame waits
// for the next slot) and `trigger = "inputs"` (the tick starts once every
// input's frame of the set has arrived; the slot's deadline is the fallback):
//   latency   pose out (after the step) - frame arrival, per latched frame
//   waiting   tick start - frame arrival: the part of the latency before
//             the work (the wait for the slot, or for the trigger's poll and
//             the wake-up); its share is summed waiting / summed latency
//
// Then the sinks: the same runtime paced in real time at 1 kHz, three ways in
// the same run: no sink; a frame log (fdatasync every 1000 frames) and a UDP
// stream written in the tick thread; the same two through sinewd's I/O
// threads (AsyncSink). The p99 ratio of the last to the first is what the
// I/O threads buy. Every setup runs with the same thread placement, the one
// the daemon's [realtime] table gives a board: the tick thread pinned to
// --tick-cpu at SCHED_FIFO --tick-fifo, the I/O threads and the loopback
// receiver pinned to --io-cpu, the I/O threads at SCHED_FIFO --io-fifo (each
// step applied when permitted and reported). Defaults on a machine with two
// or more CPUs: tick on the last CPU at 80, I/O on CPU 0 at 40; a CPU of -1
// and a priority of 0 leave the placement to the kernel.
//   sinew-bench-latency [--ticks N] [--paced-ticks N] [--trigger-poll-us U]
//                       [--tick-cpu C] [--io-cpu C] [--tick-fifo P] [--io-fifo P]
#include <netinet/in.h>
#include <pthread.h>
#include <sched.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <thread>
#include <vector>

#include "firmware/rig/loaded_rig.hpp"
#include "firmware/runtime/async_sink.hpp"
#include "firmware/runtime/realtime.hpp"
#include "firmware/runtime/runtime.hpp"
#include "firmware/runtime/tick_trigger.hpp"
#include "hal/can/can_input_source.hpp"
#include "hal/can/joint_stream_decoder.hpp"
#include "hal/can/sim/simulated_rig_bus.hpp"
#include "hal/common/monotonic_clock.hpp"
#include "hal/output/frame_log_writer.hpp"
#include "hal/output/udp_sender.hpp"
#include "host_tools/bench/common/bench_summary.hpp"

namespace {

using namespace sinew;

class CountingSink final : public hal::OutputSink {
 public:
  const char* name() const override { return "counter"; }
  bool write(const hal::PoseFrame& frame) override {
    checksum_ += static_cast<uint64_t>(frame.position[0][frame.vertex_count / 2]);
    return true;
  }
  void flush() override {}
  std::string status_line() const override { return std::to_string(checksum_); }

 private:
  uint64_t checksum_ = 0;
};

double percentile(std::vector<uint64_t> v, double p) {
  if (v.empty()) return 0;
  std::sort(v.begin(), v.end());
  return static_cast<double>(v[static_cast<size_t>(p * static_cast<double>(v.size() - 1))]) / 1000.0;
}

void run(const char* builtin, size_t ticks) {
  firmware::LoadedRig rig;
  std::string error;
  if (!firmware::load_rig(builtin, "", &rig, &error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    std::exit(1);
  }
  constexpr uint64_t kPeriod = 1'000'000;  // 1 kHz ticks
  std::vector<hal::sim::InputRange> ranges(rig.rig.input_count);
  for (const rig::JointRecord& j : rig.rig.joints)
    for (uint32_t d = 0; d < j.dof_count; ++d) ranges[j.first_input + d] = {j.dof_min[d], j.dof_max[d]};
  hal::sim::SimulatedRigOptions options;
  options.period_ns = 2'000'000;  // each input at 500 Hz
  options.offset_ns = 300'000;    // 0.3 ms after a tick: a frame waits 0.7 ms for the next
  auto bus = std::make_unique<hal::sim::SimulatedRigBus>(hal::sim::RigMotion(ranges), options, 0);
  auto decoder = std::make_unique<hal::can::JointStreamDecoder>();
  if (!decoder->configure(bus->stream_config(), &error)) std::exit(1);
  auto source = hal::can::CanInputSource::create("can", std::move(bus), std::move(decoder), 128, 0, &error);
  std::vector<hal::InputLimits> limits(rig.rig.input_count);
  firmware::Runtime runtime;
  if (!source || !runtime.init(rig.rig, limits, 0, &error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    std::exit(1);
  }
  runtime.add_source(std::move(source));
  runtime.add_sink(std::make_unique<CountingSink>());

  std::vector<uint64_t> steps, latencies;
  steps.reserve(ticks);
  latencies.reserve(ticks * rig.rig.input_count);
  uint64_t next_sent = options.offset_ns;
  for (size_t k = 0; k < ticks; ++k) {
    const uint64_t tick_ns = (k + 1) * kPeriod;
    const uint64_t t0 = hal::monotonic_ns();
    runtime.step(tick_ns, k);
    const uint64_t step = hal::monotonic_ns() - t0;
    steps.push_back(step);
    // Every frame sent since the previous tick was latched by this one.
    for (; next_sent <= tick_ns; next_sent += options.period_ns)
      for (size_t i = 0; i < rig.rig.input_count; ++i) latencies.push_back(tick_ns - next_sent + step);
  }
  // Baseline: the engine alone, same rig, same inputs held.
  std::vector<uint64_t> arena(engine::engine_arena_bytes(rig.rig) / 8 + 1);
  engine::Engine engine;
  engine::engine_init(rig.rig, arena.data(), arena.size() * 8, &engine);
  std::vector<int32_t> inputs(rig.rig.input_count, 0);
  std::vector<uint64_t> engine_steps;
  engine_steps.reserve(ticks);
  for (size_t k = 0; k < ticks; ++k) {
    inputs[k % inputs.size()] = static_cast<int32_t>(k * 1000003u);
    const uint64_t t0 = hal::monotonic_ns();
    engine::engine_step(&engine, inputs);
    engine_steps.push_back(hal::monotonic_ns() - t0);
  }
  const double step50 = percentile(steps, 0.5), engine50 = percentile(engine_steps, 0.5);
  std::printf(
      "%-5s %5u verts %2u inputs | step p50 %7.1f us p99 %7.1f us max %7.1f us (%4.1f %% of a 1 kHz tick) | "
      "engine alone p50 %7.1f us, runtime/engine %.2f | latency p50 %7.1f us p99 %7.1f us max %7.1f us (%zu frames)\n",
      builtin, rig.rig.vertex_count(), rig.rig.input_count, step50, percentile(steps, 0.99), percentile(steps, 1.0),
      step50 / 10.0, engine50, step50 / engine50, percentile(latencies, 0.5), percentile(latencies, 0.99),
      percentile(latencies, 1.0), latencies.size());
}

struct LiveLatency {
  std::vector<uint64_t> latency, waiting;
  uint64_t triggered = 0, fallback = 0;
};

// The runtime on `rig` fed by the simulated rig's CAN bus (each input at
// 500 Hz, 0.3 ms past every second slot), ticking on the wall clock at 1 kHz
// under `trigger` for `ticks` slots.
LiveLatency live_latency(const firmware::LoadedRig& rig, firmware::TickTrigger trigger, size_t ticks,
                         uint64_t poll_ns) {
  constexpr uint64_t kPeriod = 1'000'000;
  std::vector<hal::sim::InputRange> ranges(rig.rig.input_count);
  for (const rig::JointRecord& j : rig.rig.joints)
    for (uint32_t d = 0; d < j.dof_count; ++d) ranges[j.first_input + d] = {j.dof_min[d], j.dof_max[d]};
  hal::sim::SimulatedRigOptions options;
  options.period_ns = 2'000'000;
  options.offset_ns = 300'000;
  const uint64_t start = hal::monotonic_ns() + 2'000'000;
  std::string error;
  auto bus = std::make_unique<hal::sim::SimulatedRigBus>(hal::sim::RigMotion(ranges), options, start);
  auto decoder = std::make_unique<hal::can::JointStreamDecoder>();
  if (!decoder->configure(bus->stream_config(), &error)) std::exit(1);
  auto source = hal::can::CanInputSource::create("can", std::move(bus), std::move(decoder), 128, start, &error);
  std::vector<hal::InputLimits> limits(rig.rig.input_count);
  firmware::Runtime runtime;
  if (!source || !runtime.init(rig.rig, limits, start, &error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    std::exit(1);
  }
  runtime.add_source(std::move(source));
  runtime.add_sink(std::make_unique<CountingSink>());
  LiveLatency out;
  out.latency.reserve(ticks * rig.rig.input_count);
  out.waiting.reserve(ticks * rig.rig.input_count);
  firmware::MonotonicWaitClock wall;
  firmware::TriggeredTickClock clock(trigger, kPeriod, start + kPeriod, poll_ns);
  uint64_t next_sent = start + options.offset_ns;
  for (size_t k = 0; k < ticks; ++k) {
    const firmware::TriggeredTick tick = clock.wait_next(runtime.sources(), wall);
    const uint64_t t0 = hal::monotonic_ns();
    runtime.step(tick.time_ns, (tick.deadline_ns - start) / kPeriod - 1);
    const uint64_t done = hal::monotonic_ns();
    // Every frame stamped up to the tick's time was latched by it.
    for (; next_sent <= tick.time_ns; next_sent += options.period_ns)
      for (size_t i = 0; i < rig.rig.input_count; ++i) {
        out.latency.push_back(done - next_sent);
        out.waiting.push_back(t0 - next_sent);
      }
  }
  out.triggered = clock.triggered_ticks();
  out.fallback = clock.fallback_ticks();
  return out;
}

bool g_latency_summary_ok = true;  // every summary row was written

void run_live(const char* builtin, size_t ticks, uint64_t poll_ns) {
  firmware::LoadedRig rig;
  std::string error;
  if (!firmware::load_rig(builtin, "", &rig, &error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    std::exit(1);
  }
  double p50_periodic = 0;
  for (const firmware::TickTrigger trigger : {firmware::TickTrigger::kPeriodic, firmware::TickTrigger::kInputs}) {
    const LiveLatency r = live_latency(rig, trigger, ticks, poll_ns);
    uint64_t latency_sum = 0, waiting_sum = 0;
    for (uint64_t v : r.latency) latency_sum += v;
    for (uint64_t v : r.waiting) waiting_sum += v;
    const double p50 = percentile(r.latency, 0.5);
    if (trigger == firmware::TickTrigger::kPeriodic) p50_periodic = p50;
    std::printf(
        "%-5s live 1 kHz, trigger %-8s | arrival to output p50 %7.1f us p99 %7.1f us max %8.1f us | waiting p50 "
        "%7.1f us, %4.1f %% of the latency | p50 / periodic %.3f | ticks on arrival %llu, at the deadline %llu "
        "(%zu frames)\n",
        builtin, firmware::tick_trigger_name(trigger), p50, percentile(r.latency, 0.99), percentile(r.latency, 1.0),
        percentile(r.waiting, 0.5),
        latency_sum > 0 ? 100.0 * static_cast<double>(waiting_sum) / static_cast<double>(latency_sum) : 0.0,
        p50_periodic > 0 ? p50 / p50_periodic : 0.0, static_cast<unsigned long long>(r.triggered),
        static_cast<unsigned long long>(r.fallback), r.latency.size());
    if (trigger == firmware::TickTrigger::kInputs) {
      sinew::bench::SummaryRow row;
      row.bench = "latency";
      row.measure = std::string(builtin) + ", arrival to output p50, input-triggered ticks";
      row.figure = p50;
      row.unit = "us";
      row.baseline = "periodic ticks, same run";
      row.baseline_figure = p50_periodic;
      g_latency_summary_ok = sinew::bench::summary_row(row) && g_latency_summary_ok;
    }
  }
}

enum class SinkSetup { kNone, kInTickThread, kIoThreads, kIoThreadsPolled };

const char* setup_name(SinkSetup s) {
  switch (s) {
    case SinkSetup::kNone:
      return "no sink";
    case SinkSetup::kInTickThread:
      return "log+udp in tick thread";
    case SinkSetup::kIoThreads:
      return "log+udp on I/O threads";
    case SinkSetup::kIoThreadsPolled:
      return "log+udp, I/O polled 500us";
  }
  return "";
}

// A UDP port on loopback drained by a thread, so the stream is really sent.
class UdpDrain {
 public:
  explicit UdpDrain(int cpu) {
    fd_ = ::socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    sockaddr_in a{};
    a.sin_family = AF_INET;
    a.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
    socklen_t len = sizeof a;
    if (fd_ < 0 || ::bind(fd_, reinterpret_cast<sockaddr*>(&a), sizeof a) != 0 ||
        ::getsockname(fd_, reinterpret_cast<sockaddr*>(&a), &len) != 0) {
      std::fprintf(stderr, "sinew-bench-latency: cannot bind a loopback UDP port\n");
      std::exit(1);
    }
    timeval tv{0, 100000};
    ::setsockopt(fd_, SOL_SOCKET, SO_RCVTIMEO, &tv, sizeof tv);
    port_ = ntohs(a.sin_port);
    thread_ = std::thread([this] {
      std::vector<uint8_t> buf(65536);
      while (!stop_.load()) (void)::recv(fd_, buf.data(), buf.size(), 0);
    });
    if (cpu >= 0) (void)firmware::apply_thread_realtime(thread_.native_handle(), 0, cpu, "receiver");
  }
  ~UdpDrain() {
    stop_.store(true);
    thread_.join();
    ::close(fd_);
  }
  uint16_t port() const { return port_; }

 private:
  int fd_ = -1;
  uint16_t port_ = 0;
  std::atomic<bool> stop_{false};
  std::thread thread_;
};

void sleep_until_ns(uint64_t t) {
  timespec ts{static_cast<time_t>(t / 1'000'000'000u), static_cast<long>(t % 1'000'000'000u)};
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

// The runtime on `rig`, ticking in real time at 1 kHz for `ticks`, with the
// sinks of `setup`. Returns the step times.
// Where the threads run: the tick thread (the caller), the I/O threads and
// the receiver.
struct Placement {
  int tick_cpu = -1, io_cpu = -1, tick_fifo = 0, io_fifo = 0;
};

std::vector<uint64_t> paced_steps(const firmware::LoadedRig& rig, SinkSetup setup, size_t ticks,
                                  const std::string& log_path, uint16_t udp_port, const Placement& placement,
                                  std::string* sink_report) {
  std::string error;
  std::vector<hal::InputLimits> limits(rig.rig.input_count);
  firmware::Runtime runtime;
  if (!runtime.init(rig.rig, limits, 0, &error)) std::exit(1);
  hal::output::FrameShape shape;
  shape.vertex_count = rig.rig.vertex_count();
  shape.input_count = rig.rig.input_count;
  shape.length_exponent = rig.rig.length_exponent;
  std::unique_ptr<hal::OutputSink> sinks[2];
  if (setup != SinkSetup::kNone) {
    std::remove(log_path.c_str());
    auto log = std::make_unique<hal::output::FrameLogWriter>();
    auto udp = std::make_unique<hal::output::UdpSender>();
    hal::output::FrameLogOptions log_options;
    log_options.sync_every_frames = 1000;
    if (!log->open(log_path, shape, log_options, &error) || !udp->open("127.0.0.1", udp_port, shape, {}, &error)) {
      std::fprintf(stderr, "sinew-bench-latency: %s\n", error.c_str());
      std::exit(1);
    }
    log->set_name("log");
    udp->set_name("udp");
    sinks[0] = std::move(log);
    sinks[1] = std::move(udp);
  }
  for (auto& sink : sinks) {
    if (!sink) continue;
    if (setup == SinkSetup::kIoThreads || setup == SinkSetup::kIoThreadsPolled) {
      const firmware::FrameDims dims{rig.rig.vertex_count(), rig.rig.input_count, false};
      std::string report;
      firmware::AsyncSinkOptions options;
      options.fifo_priority = placement.io_fifo;
      options.cpu = placement.io_cpu;
      if (setup == SinkSetup::kIoThreadsPolled) options.poll_ns = 500'000;
      sink = std::make_unique<firmware::AsyncSink>(std::move(sink), dims, options, &report);
    }
    runtime.add_sink(std::move(sink));
  }
  // The tick thread's placement, taken after the sinks' threads exist so
  // they do not inherit it, and given back at the end; what was not
  // permitted is said once.
  firmware::RealtimeOptions tick;
  tick.fifo_priority = placement.tick_fifo;
  tick.cpu = placement.tick_cpu;
  const std::string placed = firmware::apply_realtime(tick);
  static bool placement_reported = false;
  if (!placement_reported && !placed.empty()) std::printf("tick thread: %s", placed.c_str());
  placement_reported = true;
  std::vector<uint64_t> steps;
  steps.reserve(ticks);
  const uint64_t start = hal::monotonic_ns() + 1'000'000;
  constexpr uint64_t kPeriod = 1'000'000;
  for (size_t k = 0; k < ticks; ++k) {
    const uint64_t tick_ns = start + k * kPeriod;
    sleep_until_ns(tick_ns);
    const uint64_t t0 = hal::monotonic_ns();
    runtime.step(tick_ns, k);
    steps.push_back(hal::monotonic_ns() - t0);
  }
  sched_param normal{};
  (void)pthread_setschedparam(pthread_self(), SCHED_OTHER, &normal);
  cpu_set_t all;
  CPU_ZERO(&all);
  for (long c = 0; c < ::sysconf(_SC_NPROCESSORS_ONLN) && c < CPU_SETSIZE; ++c) CPU_SET(static_cast<size_t>(c), &all);
  (void)pthread_setaffinity_np(pthread_self(), sizeof all, &all);
  const uint64_t lost = runtime.close_sinks();
  *sink_report = "frames lost by the sinks " + std::to_string(lost);
  std::remove(log_path.c_str());
  return steps;
}

void run_sinks(const char* builtin, size_t ticks, const Placement& placement) {
  firmware::LoadedRig rig;
  std::string error;
  if (!firmware::load_rig(builtin, "", &rig, &error)) {
    std::fprintf(stderr, "%s\n", error.c_str());
    std::exit(1);
  }
  char dir_template[] = "/tmp/sinew-bench-XXXXXX";
  const char* dir = ::mkdtemp(dir_template);
  if (dir == nullptr) std::exit(1);
  const std::string log_path = std::string(dir) + "/bench.log";
  UdpDrain drain(placement.io_cpu);
  double p99_none = 0;
  for (SinkSetup setup :
       {SinkSetup::kNone, SinkSetup::kInTickThread, SinkSetup::kIoThreads, SinkSetup::kIoThreadsPolled}) {
    std::string report;
    const std::vector<uint64_t> steps = paced_steps(rig, setup, ticks, log_path, drain.port(), placement, &report);
    const double p99 = percentile(steps, 0.99);
    if (setup == SinkSetup::kNone) p99_none = p99;
    std::printf("%-5s paced 1 kHz, %-26s | step p50 %7.1f us p99 %7.1f us max %8.1f us | p99 / no sink %.3f%s%s\n",
                builtin, setup_name(setup), percentile(steps, 0.5), p99, percentile(steps, 1.0), p99 / p99_none,
                setup == SinkSetup::kNone ? "" : " | ", setup == SinkSetup::kNone ? "" : report.c_str());
    if (setup == SinkSetup::kIoThreadsPolled) {
      sinew::bench::SummaryRow row;
      row.bench = "latency";
      row.measure = std::string(builtin) + ", paced 1 kHz, log + UDP sinks on polled I/O threads, step p99";
      row.figure = p99;
      row.unit = "us";
      row.baseline = "no sink, same run";
      row.baseline_figure = p99_none;
      row.target = sinew::bench::ratio_at_most(1.05);
      row.target_source = "real-time output issue: p99 within 5 % of the no-sink run";
      g_latency_summary_ok = sinew::bench::summary_row(row) && g_latency_summary_ok;
    }
  }
  ::rmdir(dir);
}

}  // namespace

int main(int argc, char** argv) {
  size_t ticks = 5000, paced_ticks = 5000;
  uint64_t poll_ns = 20'000;
  for (int i = 1; i + 1 < argc; ++i) {
    if (std::strcmp(argv[i], "--ticks") == 0) ticks = static_cast<size_t>(std::strtoull(argv[i + 1], nullptr, 10));
    if (std::strcmp(argv[i], "--paced-ticks") == 0)
      paced_ticks = static_cast<size_t>(std::strtoull(argv[i + 1], nullptr, 10));
    if (std::strcmp(argv[i], "--trigger-poll-us") == 0) poll_ns = std::strtoull(argv[i + 1], nullptr, 10) * 1000;
  }
  if (poll_ns == 0) poll_ns = 1000;
  const long cpus = ::sysconf(_SC_NPROCESSORS_ONLN);
  Placement placement;
  if (cpus >= 2) placement = {static_cast<int>(cpus - 1), 0, 80, 40};
  for (int i = 1; i + 1 < argc; ++i) {
    const int v = static_cast<int>(std::strtol(argv[i + 1], nullptr, 10));
    if (std::strcmp(argv[i], "--tick-cpu") == 0) placement.tick_cpu = v;
    if (std::strcmp(argv[i], "--io-cpu") == 0) placement.io_cpu = v;
    if (std::strcmp(argv[i], "--tick-fifo") == 0) placement.tick_fifo = v;
    if (std::strcmp(argv[i], "--io-fifo") == 0) placement.io_fifo = v;
  }
  if (ticks == 0) ticks = 1;
  if (paced_ticks == 0) paced_ticks = 1;
  std::printf("sinew-bench-latency: %zu ticks at 1 kHz (virtual deadlines), frames at 500 Hz per input\n", ticks);
  run("arm", ticks);
  run("hand", ticks);
  std::printf(
      "arrival to output: %zu slots in real time at 1 kHz per trigger, frames at 500 Hz per input, trigger poll %.0f "
      "us, in this run\n",
      paced_ticks, static_cast<double>(poll_ns) / 1000.0);
  run_live("arm", paced_ticks, poll_ns);
  run_live("hand", paced_ticks, poll_ns);
  std::printf(
      "sinks: %zu ticks paced in real time at 1 kHz per setup, in this run; tick thread cpu %d fifo %d, I/O "
      "threads cpu %d fifo %d\n",
      paced_ticks, placement.tick_cpu, placement.tick_fifo, placement.io_cpu, placement.io_fifo);
  run_sinks("arm", paced_ticks, placement);
  run_sinks("hand", paced_ticks, placement);
  return g_latency_summary_ok ? 0 : 1;
}
