// Cost of one GpioSource::latch() on the simulated twin with N encoder edges
// pending (edge injection included), beside the baseline of the bare
// decoder fed the same edges, measured in the same run: the ratio is the
// price of the staging, timestamp merge and dispatch around the decoder.
//   sinew-bench-gpio [--benchmark_filter=...]
#include <benchmark/benchmark.h>

#include <array>
#include <chrono>

#include "hal/common/input_health.hpp"
#include "hal/gpio/gpio_source.hpp"
#include "hal/gpio/simulated_gpio.hpp"

namespace sinew::hal::gpio {
namespace {

// ns per tick of the bare decoder for `edges` edges (the baseline).
double decoder_ns_per_tick(int edges) {
  QuadratureDecoder d;
  d.reset(false, false, 0);
  const int ticks = 20000;
  uint64_t t = 0;
  int pos = 0;
  const auto start = std::chrono::steady_clock::now();
  for (int k = 0; k < ticks; ++k) {
    for (int i = 0; i < edges; ++i) {
      const int next = (pos + 1) % 4;
      const uint8_t diff = static_cast<uint8_t>(kQuadratureForward[pos] ^ kQuadratureForward[next]);
      d.on_edge(diff == 2 ? 0 : 1, (kQuadratureForward[next] & diff) != 0, ++t);
      pos = next;
    }
    d.settle(t);
  }
  benchmark::DoNotOptimize(d.count());
  return std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - start).count() / ticks;
}

void BM_LatchEncoderEdges(benchmark::State& state) {
  const int edges = static_cast<int>(state.range(0));
  SimulatedGpio wire(16);
  GpioSourceConfig c;
  c.encoders.resize(1);
  c.limits.resize(1);
  c.limits[0].line = 2;
  std::string error;
  auto source = GpioSource::create(c, wire.chip(), &error);
  if (!source) {
    state.SkipWithError(error.c_str());
    return;
  }
  hal::InputHealth health;
  const hal::InputLimits limits[1] = {};
  const int32_t initial[1] = {};
  health.init(limits, initial, 0);
  std::array<JointSample, 4> out{};
  uint64_t t = 0;
  int pos = 0;
  const auto start = std::chrono::steady_clock::now();
  for (auto _ : state) {
    for (int i = 0; i < edges; ++i) {
      pos = (pos + 1) % 4;
      ++t;
      wire.set_level(0, (kQuadratureForward[pos] & 2) != 0, t);
      wire.set_level(1, (kQuadratureForward[pos] & 1) != 0, t);
    }
    benchmark::DoNotOptimize(source->latch(t, out, health));
  }
  const double latch_ns = std::chrono::duration<double, std::nano>(std::chrono::steady_clock::now() - start).count() /
                          static_cast<double>(state.iterations());
  const double baseline = decoder_ns_per_tick(edges);
  state.counters["edges"] = edges;
  state.counters["latch_ns"] = latch_ns;
  state.counters["decoder_ns"] = baseline;
  state.counters["ratio_vs_decoder"] = baseline > 0 ? latch_ns / baseline : 0;
}
BENCHMARK(BM_LatchEncoderEdges)->Arg(0)->Arg(8)->Arg(16)->Arg(32);

}  // namespace
}  // namespace sinew::hal::gpio

BENCHMARK_MAIN();
