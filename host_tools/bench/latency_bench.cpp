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
//   sinew-bench-latency [--ticks N]
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <string>
#include <vector>

#include "firmware/daemon/loaded_rig.hpp"
#include "firmware/runtime/runtime.hpp"
#include "hal/can/can_input_source.hpp"
#include "hal/can/joint_stream_decoder.hpp"
#include "hal/can/sim/simulated_rig_bus.hpp"
#include "hal/common/monotonic_clock.hpp"

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

}  // namespace

int main(int argc, char** argv) {
  size_t ticks = 5000;
  for (int i = 1; i + 1 < argc; ++i)
    if (std::strcmp(argv[i], "--ticks") == 0) ticks = static_cast<size_t>(std::strtoull(argv[i + 1], nullptr, 10));
  if (ticks == 0) ticks = 1;
  std::printf("sinew-bench-latency: %zu ticks at 1 kHz (virtual deadlines), frames at 500 Hz per input\n", ticks);
  run("arm", ticks);
  run("hand", ticks);
  return 0;
}
