// SPH elastic-joint cost on the built-in arm's elbow (sph-elastic-joints-tresca,
// table 1 extended to 8000 particles): one 1 kHz tick = engine step (LBS skin)
// + sph_step + eq. (2) skin coupling, against the LBS-only engine step of the
// same rig measured in the same run. Prints per count: step time, ratio to
// LBS, neighbour pairs per second, share of the 1 ms tick, and a closing table
// with the time per particle (flat when the growth is linear).
//   sinew-bench-sph [--benchmark_min_time=0.5]
#include <benchmark/benchmark.h>

#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "host_tools/layers/sph/sph_builder.hpp"
#include "host_tools/rigc/builtin_rigs.hpp"
#include "host_tools/rigc/rig_spec.hpp"
#include "sim_core/engine/engine.hpp"
#include "sim_core/sph/sph_step.hpp"

namespace {

namespace rigc = sinew::rigc;
namespace sph = sinew::sph;
namespace engine = sinew::engine;
using Clock = std::chrono::steady_clock;

constexpr int32_t kForceY = 5 << 16;  // 5 N toward +y on the wrist (figure 3's load), Q16.16

// The arm (LBS skin) with its engine and an SPH elbow of n particles.
struct Rig {
  rigc::RigSpec spec;
  std::vector<uint64_t> blob, rig_arena, engine_arena, sph_arena;
  sinew::rig::Rig rig;
  engine::Engine engine;
  std::vector<int32_t> inputs;
  sinew::layers::SphBuilt built;
  sph::SphModel model;
  sph::SphState state;
};

[[noreturn]] void die(const std::string& what) {
  std::fprintf(stderr, "sinew-bench-sph: %s\n", what.c_str());
  std::exit(1);
}

std::unique_ptr<Rig> make_rig(uint32_t particles) {
  auto r = std::make_unique<Rig>();
  r->spec = rigc::builtin_arm(rigc::SkinChoice::kLinear);
  std::vector<uint8_t> bytes;
  rigc::CompileReport report;
  std::string error;
  if (!rigc::compile_rig(r->spec, &bytes, &report, &error)) die(error);
  r->blob.assign(bytes.size() / 8 + 1, 0);
  std::memcpy(r->blob.data(), bytes.data(), bytes.size());
  const auto* data = reinterpret_cast<const uint8_t*>(r->blob.data());
  size_t rig_bytes = 0;
  if (!sinew::rig::rig_validate(data, bytes.size(), &rig_bytes).ok()) die("rig validate");
  r->rig_arena.assign(rig_bytes / 8 + 1, 0);
  if (!sinew::rig::rig_init(data, bytes.size(), r->rig_arena.data(), r->rig_arena.size() * 8, &r->rig).ok())
    die("rig init");
  r->engine_arena.assign(engine::engine_arena_bytes(r->rig) / 8 + 1, 0);
  if (!engine::engine_init(r->rig, r->engine_arena.data(), r->engine_arena.size() * 8, &r->engine)) die("engine init");
  r->inputs.assign(r->rig.input_count, 0);
  sinew::layers::SphBuildOptions options;
  options.particle_count = particles;
  if (!sinew::layers::build_sph(r->spec, options, &r->built, &error)) die(error);
  r->model = r->built.model();
  r->sph_arena.assign(sph::sph_state_bytes(r->model) / 8 + 1, 0);
  const sph::SphStatus s =
      sph::sph_init(r->model, r->engine.model, r->sph_arena.data(), r->sph_arena.size() * 8, &r->state);
  if (!s.ok()) die(s.message);
  return r;
}

// Built once per count, outside the timed region.
Rig& rig_for(uint32_t particles) {
  static std::map<uint32_t, std::unique_ptr<Rig>> cache;
  auto& slot = cache[particles];
  if (!slot) slot = make_rig(particles);
  return *slot;
}

// LBS-only engine step of the same rig: the baseline, timed in the same run
// (also inside each SPH case, so a filtered run still has its ratio).
double lbs_step_seconds(Rig& r, int steps) {
  const auto start = Clock::now();
  for (int s = 0; s < steps; ++s) {
    engine::engine_step(&r.engine, r.inputs);
    benchmark::DoNotOptimize(r.engine.vertices.position[0].data());
  }
  return std::chrono::duration<double>(Clock::now() - start).count() / steps;
}

void tick(Rig& r) {
  engine::engine_step(&r.engine, r.inputs);
  sph::SphInputs in;
  in.transforms = r.engine.model;
  in.force = {0, kForceY, 0};
  in.tresca = true;
  const sph::SphStatus s = sph::sph_step(&r.state, in);
  if (!s.ok()) die(s.message);
  sph::sph_apply_skin(r.state, r.engine.vertices.position);
  benchmark::DoNotOptimize(r.state.position[0].data());
}

struct Row {
  double step_s = 0, lbs_s = 0, pairs_per_s = 0;
};
std::map<uint32_t, Row>& rows() {
  static std::map<uint32_t, Row> r;
  return r;
}

void BM_EngineLbsOnly(benchmark::State& state) {
  Rig& r = rig_for(500);
  for (auto _ : state) {
    engine::engine_step(&r.engine, r.inputs);
    benchmark::DoNotOptimize(r.engine.vertices.position[0].data());
  }
  state.counters["vertices"] = static_cast<double>(r.rig.vertex_count());
}

void BM_SphTick(benchmark::State& state) {
  const auto n = static_cast<uint32_t>(state.range(0));
  Rig& r = rig_for(n);
  const double lbs = lbs_step_seconds(r, 200);
  for (int t = 0; t < 20; ++t) tick(r);  // past the first contact transient
  double seconds = 0, pairs = 0;
  for (auto _ : state) {
    const auto start = Clock::now();
    tick(r);
    seconds += std::chrono::duration<double>(Clock::now() - start).count();
    pairs += static_cast<double>(r.state.stats.neighbour_pairs);
  }
  const double iters = static_cast<double>(state.iterations());
  Row& row = rows()[n];
  row.step_s = seconds / iters;
  row.lbs_s = lbs;
  row.pairs_per_s = pairs / seconds;
  state.counters["particles"] = n;
  state.counters["lbs_us"] = lbs * 1e6;
  state.counters["ratio_vs_lbs"] = row.step_s / lbs;
  state.counters["neighbours_per_s"] = row.pairs_per_s;
  state.counters["tick_share_pct"] = row.step_s / 1e-3 * 100.0;
  state.counters["bend_deg"] = static_cast<double>(static_cast<int32_t>(r.state.bend)) / 4294967296.0 * 360.0;
}

BENCHMARK(BM_EngineLbsOnly)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SphTick)->Arg(500)->Arg(1000)->Arg(2000)->Arg(4000)->Arg(8000)->Unit(benchmark::kMicrosecond);

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  if (rows().empty()) return 0;
  std::printf("\nsph tick (engine LBS + sph_step + eq. (2) skin) vs LBS-only engine step, 1 kHz budget\n");
  std::printf("  particles  step(us)  LBS(us)  ratio  us/particle  neighbours/s  tick share\n");
  for (const auto& [n, row] : rows())
    std::printf("  %9u  %8.1f  %7.2f  %5.1f  %11.4f  %12.3g  %9.1f%%\n", n, row.step_s * 1e6, row.lbs_s * 1e6,
                row.step_s / row.lbs_s, row.step_s * 1e6 / n, row.pairs_per_s, row.step_s / 1e-3 * 100.0);
  return 0;
}
