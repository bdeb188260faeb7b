// SPH elastic-joint cost on the built-in arm's elbow (sph-elastic-joints-tresca,
// table 1 extended to 8000 particles). Per particle count, in one run:
//   - sph_step alone (2 substeps, the builder's default) and the whole 1 kHz
//     tick (engine step with LBS skin + sph_step + eq. (2) skin coupling);
//   - the same sph step by the first implementation (tests/sim_core/sph/
//     sph_reference_v1, per-particle lists, both sides of every pair): the
//     baseline, on an identical state, so the ratio is the speed-up;
//   - the LBS-only engine step of the same rig.
// The closing table prints neighbour pairs per second (list entries per
// second of sph_step), µs per tick and share of a 1 ms tick, µs per particle
// (flat when growth is linear), and the performance targets with pass/fail:
//   >= 1e8 neighbour pairs per second; sph_step at 1000 particles within 30 %
//   of a 1 ms tick; time per particle at 8000 within 1.3x that at 1000.
// Times are the thread's CPU time (clock_gettime), steadier on a shared machine.
//   sinew-bench-sph [--benchmark_min_time=0.5]
#include <benchmark/benchmark.h>
#include <time.h>

#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include "host_tools/bench/common/bench_summary.hpp"
#include "host_tools/layers/sph/sph_builder.hpp"
#include "host_tools/layers/sph/sph_reference_v1.hpp"
#include "host_tools/rigc/builtin_rigs.hpp"
#include "host_tools/rigc/rig_spec.hpp"
#include "sim_core/engine/engine.hpp"
#include "sim_core/sph/sph_step.hpp"

namespace {

namespace rigc = sinew::rigc;
namespace sph = sinew::sph;
namespace engine = sinew::engine;
namespace ref = sinew::sph_reference_v1;

// The thread's CPU time: the machine may be shared, and a tick's cost is the
// CPU time it needs (the board runs the tick thread alone on its core).
double thread_seconds() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) + static_cast<double>(t.tv_nsec) * 1e-9;
}

constexpr int32_t kForceY = 5 << 16;  // 5 N toward +y on the wrist (figure 3's load), Q16.16
constexpr double kPairsTarget = 1e8;
constexpr double kTickShareTarget = 0.30;  // of a 1 ms tick, sph_step at 1000 particles
constexpr double kLinearTarget = 1.3;      // us/particle at 8000 over that at 1000

// The arm (LBS skin) with its engine, an SPH elbow of n particles, and the
// reference implementation's state of the same elbow.
struct Rig {
  rigc::RigSpec spec;
  std::vector<uint64_t> blob, rig_arena, engine_arena, sph_arena;
  sinew::rig::Rig rig;
  engine::Engine engine;
  std::vector<int32_t> inputs;
  sinew::layers::SphBuilt built;
  sph::SphModel model;
  sph::SphState state;
  ref::RefState reference;
};

[[noreturn]] void die(const std::string& what) {
  std::fprintf(stderr, "sinew-bench-sph: %s\n", what.c_str());
  std::exit(1);
}

// Surface tension of the tension rows (N/m): the value the term tests use
// on the arm (docs/sph.md; off on the built-in rigs).
constexpr double kBenchSurfaceTension = 1.0;

std::unique_ptr<Rig> make_rig(uint32_t particles, bool tension) {
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
  options.surface_tension = tension ? kBenchSurfaceTension : 0.0;
  if (!sinew::layers::build_sph(r->spec, options, &r->built, &error)) die(error);
  r->model = r->built.model();
  r->sph_arena.assign(sph::sph_state_bytes(r->model) / 8 + 1, 0);
  const sph::LayerStatus s =
      sph::sph_init(r->model, r->engine.model, r->sph_arena.data(), r->sph_arena.size() * 8, &r->state);
  if (!s.ok()) die(s.message);
  if (!ref::ref_init(r->model, r->engine.model, &r->reference).ok()) die("reference init");
  return r;
}

// Built once per count, outside the timed region.
Rig& rig_for(uint32_t particles, bool tension = false) {
  static std::map<std::pair<uint32_t, bool>, std::unique_ptr<Rig>> cache;
  auto& slot = cache[{particles, tension}];
  if (!slot) slot = make_rig(particles, tension);
  return *slot;
}

// LBS-only engine step of the same rig: timed in the same run (also inside
// each SPH case, so a filtered run still has its ratio).
double lbs_step_seconds(Rig& r, int steps) {
  const double start = thread_seconds();
  for (int s = 0; s < steps; ++s) {
    engine::engine_step(&r.engine, r.inputs);
    benchmark::DoNotOptimize(r.engine.vertices.position[0].data());
  }
  return (thread_seconds() - start) / steps;
}

sph::SphInputs inputs_of(const Rig& r) {
  sph::SphInputs in;
  in.transforms = r.engine.model;
  in.force = {0, kForceY, 0};
  in.tresca = true;
  return in;
}

// One tick; returns the seconds spent in the sph step alone.
double tick(Rig& r, bool reference) {
  engine::engine_step(&r.engine, r.inputs);
  const sph::SphInputs in = inputs_of(r);
  const double start = thread_seconds();
  const sph::LayerStatus s = reference ? ref::ref_step(&r.reference, in) : sph::sph_step(&r.state, in);
  const double sph_s = thread_seconds() - start;
  if (!s.ok()) die(s.message);
  if (reference)
    ref::ref_apply_skin(r.reference, r.engine.vertices.position);
  else
    sph::sph_apply_skin(r.state, r.engine.vertices.position);
  benchmark::DoNotOptimize(r.engine.vertices.position[0].data());
  return sph_s;
}

struct Row {
  double tick_s = 0, sph_s = 0, ref_sph_s = 0, lbs_s = 0, pairs_per_s = 0, ref_pairs_per_s = 0;
  double tension_sph_s = 0;  // sph_step with the colour-field surface tension on
  uint32_t substeps = 0;
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

void run_ticks(benchmark::State& state, bool reference, bool tension = false) {
  const auto n = static_cast<uint32_t>(state.range(0));
  Rig& r = rig_for(n, tension);
  const double lbs = lbs_step_seconds(r, 200);
  for (int t = 0; t < 20; ++t) tick(r, reference);  // past the first contact transient
  double seconds = 0, sph_seconds = 0, pairs = 0;
  for (auto _ : state) {
    const double start = thread_seconds();
    sph_seconds += tick(r, reference);
    seconds += thread_seconds() - start;
    pairs += static_cast<double>(reference ? r.reference.stats.neighbour_pairs : r.state.stats.neighbour_pairs);
  }
  const double iters = static_cast<double>(state.iterations());
  Row& row = rows()[n];
  if (tension) {
    row.tension_sph_s = sph_seconds / iters;
    state.counters["particles"] = n;
    state.counters["sph_us"] = sph_seconds / iters * 1e6;
    return;
  }
  row.lbs_s = lbs;
  row.substeps = r.model.params.substeps;
  if (reference) {
    row.ref_sph_s = sph_seconds / iters;
    row.ref_pairs_per_s = pairs / sph_seconds;
  } else {
    row.tick_s = seconds / iters;
    row.sph_s = sph_seconds / iters;
    row.pairs_per_s = pairs / sph_seconds;
  }
  state.counters["particles"] = n;
  state.counters["sph_us"] = sph_seconds / iters * 1e6;
  state.counters["neighbours_per_s"] = pairs / sph_seconds;
  state.counters["tick_share_pct"] = seconds / iters / 1e-3 * 100.0;
}

void BM_SphTick(benchmark::State& state) { run_ticks(state, false); }
void BM_SphTickReferenceV1(benchmark::State& state) { run_ticks(state, true); }
void BM_SphTickSurfaceTension(benchmark::State& state) { run_ticks(state, false, true); }

BENCHMARK(BM_EngineLbsOnly)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SphTick)->Arg(500)->Arg(1000)->Arg(2000)->Arg(4000)->Arg(8000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SphTickReferenceV1)->Arg(500)->Arg(1000)->Arg(2000)->Arg(4000)->Arg(8000)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_SphTickSurfaceTension)
    ->Arg(500)
    ->Arg(1000)
    ->Arg(2000)
    ->Arg(4000)
    ->Arg(8000)
    ->Unit(benchmark::kMicrosecond);

const char* verdict(bool met) { return met ? "met" : "NOT met"; }

// The bench table's rows: pairs per second and the 1000-particle step, each
// beside the first implementation timed on the same state in this run.
template <typename Rows>
bool summarise(const Rows& all) {
  namespace sb = sinew::bench;
  bool ok = true;
  const auto k1 = all.find(1000);
  if (k1 == all.end() || k1->second.sph_s <= 0) return ok;
  const Row& r = k1->second;
  sb::SummaryRow pairs;
  pairs.bench = "sph";
  pairs.measure = "neighbour pairs per second, 1000 particles";
  pairs.figure = r.pairs_per_s;
  pairs.unit = "pairs/s";
  pairs.baseline = "first implementation, same state";
  pairs.baseline_figure = r.ref_pairs_per_s;
  pairs.target = sb::figure_at_least(kPairsTarget);
  pairs.target_source = "performance issue: >= 1e8 neighbour pairs per second";
  ok = sb::summary_row(pairs) && ok;
  sb::SummaryRow step;
  step.bench = "sph";
  step.measure = "sph_step, 1000 particles, " + std::to_string(r.substeps) + " substeps";
  step.figure = r.sph_s * 1e6;
  step.unit = "us";
  step.baseline = "first implementation, same state";
  step.baseline_figure = r.ref_sph_s * 1e6;
  step.target = sb::figure_at_most(kTickShareTarget * 1000);
  step.target_source = "performance issue: within 30 % of a 1 kHz tick";
  ok = sb::summary_row(step) && ok;
  return ok;
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  if (rows().empty()) return 0;
  std::printf("\nsph_step vs the first implementation (reference v1) on the same state, and the whole tick\n");
  std::printf("(engine LBS + sph_step + eq. (2) skin); 1 kHz budget\n");
  std::printf(
      "  particles  substeps  sph(us)  ref v1(us)  speed-up  pairs/s   ref pairs/s  tick(us)  LBS(us)  tick share  "
      "sph us/particle\n");
  for (const auto& [n, row] : rows())
    std::printf("  %9u  %8u  %7.1f  %10.1f  %8.1f  %8.3g  %11.3g  %8.1f  %7.1f  %9.1f%%  %15.4f\n", n, row.substeps,
                row.sph_s * 1e6, row.ref_sph_s * 1e6, row.sph_s > 0 ? row.ref_sph_s / row.sph_s : 0.0, row.pairs_per_s,
                row.ref_pairs_per_s, row.tick_s * 1e6, row.lbs_s * 1e6, row.tick_s / 1e-3 * 100.0, row.sph_s * 1e6 / n);
  const auto& all = rows();
  std::printf(
      "\nsurface tension (sigma %.1f N/m, colour field in the same pass over the pairs) against none, same run\n",
      kBenchSurfaceTension);
  std::printf("  particles  sph(us)  with tension(us)  ratio\n");
  for (const auto& [n, row] : all)
    if (row.tension_sph_s > 0 && row.sph_s > 0)
      std::printf("  %9u  %7.1f  %16.1f  %5.2f\n", n, row.sph_s * 1e6, row.tension_sph_s * 1e6,
                  row.tension_sph_s / row.sph_s);
  std::printf("\ntargets\n");
  double worst_pairs = 0;
  for (const auto& [n, row] : all)
    if (row.pairs_per_s > 0 && (worst_pairs == 0 || row.pairs_per_s < worst_pairs)) worst_pairs = row.pairs_per_s;
  if (worst_pairs > 0)
    std::printf("  neighbour pairs per second >= %.0e: lowest %.3g: %s\n", kPairsTarget, worst_pairs,
                verdict(worst_pairs >= kPairsTarget));
  const auto k1 = all.find(1000);
  if (k1 != all.end() && k1->second.sph_s > 0) {
    const Row& r = k1->second;
    std::printf("  sph_step at 1000 particles, %u substeps, <= %.0f%% of a 1 ms tick: %.1f us = %.1f%%: %s\n",
                r.substeps, kTickShareTarget * 100, r.sph_s * 1e6, r.sph_s / 1e-3 * 100, verdict(r.sph_s <= 3e-4));
    std::printf("  (whole tick with the engine's LBS step: %.1f us = %.1f%% of 1 ms: %s)\n", r.tick_s * 1e6,
                r.tick_s / 1e-3 * 100, verdict(r.tick_s <= 3e-4));
    const auto k8 = all.find(8000);
    if (k8 != all.end() && k8->second.sph_s > 0) {
      const double growth = (k8->second.sph_s / 8000) / (r.sph_s / 1000);
      std::printf("  linear growth to 8000 (us/particle at 8000 over at 1000 <= %.1f): %.2f: %s\n", kLinearTarget,
                  growth, verdict(growth <= kLinearTarget));
    }
  }
  return summarise(all) ? 0 : 1;
}
