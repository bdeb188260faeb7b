// Per-step cost of the anatomy layers beside skinning, on the built-in arm
// and on the largest shared asset (tests/data/generic-hand_left.glb, skin
// layer only: it has no muscles), the relaxation cost per iteration per
// vertex, and the anatomically-based paper's workload (30 relaxations of
// 75 000 vertices: 25 s in 1997) measured on a 75 000-vertex tube, and the
// arm's dynamic skin (LEMAN §3) per tick at 100 Hz and 1 kHz against LBS
// and against the tick's period.
//   sinew-bench-anatomy [--benchmark_min_time=0.5]
// Prints Google Benchmark's table, then the per-layer table with ratios
// against LBS of the same rig measured in the same run.
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <memory>
#include <string>
#include <vector>

#include "host_tools/bench/common/bench_summary.hpp"
#include "host_tools/layers/anatomy/anatomy_build.hpp"
#include "host_tools/rigc/builtin_rigs.hpp"
#include "host_tools/rigc/gltf_import.hpp"
#include "sim_core/elastic_skin/skin_step.hpp"
#include "sim_core/engine/engine.hpp"
#include "sim_core/muscle/muscle_step.hpp"

namespace {

namespace ab = sinew::anatomy_build;
namespace es = sinew::elastic_skin;
namespace muscle = sinew::muscle;
namespace rigc = sinew::rigc;

bool g_summary_failed = false;  // a summary row could not be written

// A rig, its engine and both layers, ready to step.
struct Scene {
  std::string name, error;
  bool ok = false;
  rigc::RigSpec spec;
  std::vector<uint64_t> blob, rig_arena, engine_arena, muscle_memory, skin_memory;
  sinew::rig::Rig rig;
  sinew::engine::Engine engine;
  ab::AnatomyModel model;
  muscle::MuscleModel mm;
  es::SkinModel sm;
  muscle::MuscleState ms;
  es::SkinState ss;
  std::vector<int32_t> inputs;
  uint32_t tick_hz = 1000;  // the loop rate the dynamic skin steps at

  Scene(std::string label, rigc::RigSpec s, ab::AnatomySpec (*anatomy)(const rigc::RigSpec&), int iterations,
        std::string load_error = "")
      : name(std::move(label)), error(std::move(load_error)), spec(std::move(s)) {
    ok = error.empty() && init(anatomy, iterations);
  }
  Scene(const Scene&) = delete;  // spans point into the members

  bool init(ab::AnatomySpec (*anatomy)(const rigc::RigSpec&), int iterations) {
    std::vector<uint8_t> bytes;
    rigc::CompileReport report;
    if (!rigc::compile_rig(spec, &bytes, &report, &error)) return false;
    blob.assign(bytes.size() / 8 + 1, 0);
    std::memcpy(blob.data(), bytes.data(), bytes.size());
    const auto* data = reinterpret_cast<const uint8_t*>(blob.data());
    size_t rig_bytes = 0;
    if (!sinew::rig::rig_validate(data, bytes.size(), &rig_bytes).ok()) return error = "rig blob", false;
    rig_arena.assign(rig_bytes / 8 + 1, 0);
    if (!sinew::rig::rig_init(data, bytes.size(), rig_arena.data(), rig_arena.size() * 8, &rig).ok())
      return error = "rig init", false;
    engine_arena.assign(sinew::engine::engine_arena_bytes(rig) / 8 + 1, 0);
    if (!sinew::engine::engine_init(rig, engine_arena.data(), engine_arena.size() * 8, &engine))
      return error = "engine init", false;
    inputs.assign(rig.input_count, 0);
    ab::AnatomySpec a = anatomy(spec);
    a.skin.iterations = iterations;
    if (!ab::build_anatomy(rig, a, &model, &error)) return false;
    mm = model.muscle_model();
    sm = model.skin_model();
    muscle_memory.assign(muscle::muscle_state_bytes(mm) / 8 + 1, 0);
    skin_memory.assign(es::skin_state_bytes(sm) / 8 + 1, 0);
    muscle::LayerStatus st = muscle::muscle_state_init(mm, muscle_memory.data(), muscle_memory.size() * 8, &ms);
    if (st.ok()) st = es::skin_state_init(sm, skin_memory.data(), skin_memory.size() * 8, &ss);
    if (!st.ok()) return error = st.message, false;
    return true;
  }
  // A pose that changes every call, so muscles are recomputed.
  void pose(uint64_t i) {
    for (size_t k = 0; k < inputs.size(); ++k)
      inputs[k] = static_cast<int32_t>(((i * 7919u + k * 104729u) % 120u) * 35791394u);  // 0..119 degrees
  }
  void step_engine(uint64_t i) {
    pose(i);
    sinew::engine::engine_step(&engine, inputs);
  }
  void step_muscles() { muscle::muscle_step(mm, engine.model, &ms); }
  // The dynamic skin needs the loop's rate; the static one ignores it.
  void step_skin() { es::skin_step(sm, mm, ms, engine.model, es::SkinTick{tick_hz, {0, 0, 0}}, &ss); }
};

// No muscles: every vertex anchors to its bones (any rig).
ab::AnatomySpec bones_only(const rigc::RigSpec& spec) {
  ab::AnatomySpec a;
  a.bones.assign(spec.joints.size(), ab::BoneSize{0.1, 0.01});
  a.skin.max_anchor_distance = 1e30;
  a.skin.collision_radius = 0;
  a.skin.bands.clear();
  return a;
}

// The arm in LEMAN's real-time regime: a few warm-started relaxations per step.
ab::AnatomySpec arm_warm(const rigc::RigSpec& spec) {
  ab::AnatomySpec a = ab::arm_anatomy(spec);
  a.skin.warm_start = true;
  return a;
}

// The arm with the dynamic skin (LEMAN §3) at its defaults: 1 kHz substeps,
// 3 reaction passes each.
ab::AnatomySpec arm_dynamic(const rigc::RigSpec& spec) {
  ab::AnatomySpec a = ab::arm_anatomy(spec);
  a.skin.solver.dynamic = true;
  return a;
}

// A 75 000-vertex tube (300 rings x 250 segments) on a two-joint chain.
rigc::RigSpec tube_75k() {
  rigc::RigSpec s;
  rigc::JointSpec root;
  root.name = "root";
  root.dofs = {{{0, 0, 1}, -90, 90}};
  rigc::JointSpec mid = root;
  mid.name = "mid";
  mid.parent = 0;
  mid.translation = {0.5, 0, 0};
  s.joints = {root, mid};
  for (int j = 0; j < 2; ++j) {
    rigc::PaletteSpec p;
    p.joint = j;
    p.inverse_bind[12] = -0.5 * j;
    s.palette.push_back(p);
  }
  const int rings = 300, seg = 250;
  for (int r = 0; r < rings; ++r)
    for (int k = 0; k < seg; ++k) {
      const double a = 2 * 3.14159265358979 * k / seg;
      rigc::VertexSpec v;
      v.position = {r / 300.0, 0.05 * std::cos(a), 0.05 * std::sin(a)};
      v.normal = {0, std::cos(a), std::sin(a)};
      const double w = std::min(1.0, std::max(0.0, (r / 300.0 - 0.4) / 0.2));
      v.influences = {{0, 1 - w}, {1, w}};
      s.vertices.push_back(v);
    }
  for (int r = 0; r + 1 < rings; ++r)
    for (int k = 0; k < seg; ++k) {
      const uint32_t a = static_cast<uint32_t>(r * seg + k), b = static_cast<uint32_t>(r * seg + (k + 1) % seg);
      s.triangles.push_back({a, a + seg, b});
      s.triangles.push_back({b, a + seg, b + seg});
    }
  s.primitives.push_back({0, static_cast<uint32_t>(s.vertices.size())});
  return s;
}

// The same at 100 Hz: the substep rate stays 1 kHz, so a tick takes 10
// substeps (max_substeps raised for rigs that ask for more).
ab::AnatomySpec arm_dynamic_100hz(const rigc::RigSpec& spec) {
  ab::AnatomySpec a = arm_dynamic(spec);
  a.skin.solver.max_substeps = 64;
  return a;
}

Scene& arm_dynamic_at(uint32_t hz) {
  static Scene s100("arm, dynamic skin, 100 Hz", rigc::builtin_arm(rigc::SkinChoice::kLinear), arm_dynamic_100hz, 1);
  static Scene s1k("arm, dynamic skin, 1 kHz", rigc::builtin_arm(rigc::SkinChoice::kLinear), arm_dynamic, 1);
  s100.tick_hz = 100;
  return hz == 100 ? s100 : s1k;
}
Scene& arm_lbs() {
  static Scene s("arm (LBS)", rigc::builtin_arm(rigc::SkinChoice::kLinear), ab::arm_anatomy, 30);
  return s;
}
Scene& arm_dqs() {
  static Scene s("arm (DQS)", rigc::builtin_arm(rigc::SkinChoice::kDualQuaternion), ab::arm_anatomy, 30);
  return s;
}
rigc::RigSpec load_hand(std::string* error) {
  rigc::GltfRig g;
  const std::string path = std::string(SINEW_SOURCE_DIR) + "/tests/data/generic-hand_left.glb";
  if (!rigc::import_gltf(path, &g, error)) return {};
  return g.spec;
}
Scene& hand_asset() {
  static std::string load_error;
  static const rigc::RigSpec spec = load_hand(&load_error);  // before the scene reads load_error
  static Scene s("generic-hand_left.glb", spec, bones_only, 30, load_error);
  return s;
}

void run_engine(benchmark::State& state, Scene& s) {
  if (!s.ok) return state.SkipWithError(s.error.c_str());
  uint64_t i = 0;
  for (auto _ : state) s.step_engine(++i);
  state.counters["vertices"] = s.rig.vertex_count();
}
void run_muscles(benchmark::State& state, Scene& s) {
  if (!s.ok) return state.SkipWithError(s.error.c_str());
  uint64_t i = 0;
  for (auto _ : state) {
    state.PauseTiming();
    s.step_engine(++i);
    state.ResumeTiming();
    s.step_muscles();
  }
}
void run_skin(benchmark::State& state, Scene& s) {
  if (!s.ok) return state.SkipWithError(s.error.c_str());
  uint64_t i = 0;
  for (auto _ : state) {
    state.PauseTiming();
    s.step_engine(++i);
    s.step_muscles();
    state.ResumeTiming();
    s.step_skin();
  }
  // Vertex relaxations per second (iterations x vertices); the summary prints ns each.
  state.counters["vertex_iterations"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * s.sm.params.iterations * s.sm.vertex_count,
                         benchmark::Counter::kIsRate);
}

BENCHMARK_CAPTURE(run_engine, arm_lbs, arm_lbs());
BENCHMARK_CAPTURE(run_engine, arm_dqs, arm_dqs());
BENCHMARK_CAPTURE(run_muscles, arm, arm_lbs());
BENCHMARK_CAPTURE(run_skin, arm_30_iterations, arm_lbs());
BENCHMARK_CAPTURE(run_skin, arm_dynamic_100hz, arm_dynamic_at(100));
BENCHMARK_CAPTURE(run_skin, arm_dynamic_1khz, arm_dynamic_at(1000));
BENCHMARK_CAPTURE(run_engine, hand_asset_skinning, hand_asset());
BENCHMARK_CAPTURE(run_skin, hand_asset_30_iterations, hand_asset());

// Mean seconds per call of f over at least `min_seconds` (and 3 calls).
template <typename F>
double mean_seconds(F&& f, double min_seconds) {
  using clock = std::chrono::steady_clock;
  const auto start = clock::now();
  int n = 0;
  double elapsed = 0;
  do {
    f(static_cast<uint64_t>(n));
    ++n;
    elapsed = std::chrono::duration<double>(clock::now() - start).count();
  } while (n < 3 || elapsed < min_seconds);
  return elapsed / n;
}

// The relaxation's cost per vertex per iteration, beside one skinning pass's
// cost per vertex of the same rig (same run), for the bench table.
void report_relaxation(const std::string& name, double skin_seconds, double skinning_seconds, const Scene& s) {
  const double per_vertex = static_cast<double>(s.sm.vertex_count);
  sinew::bench::SummaryRow row;
  row.bench = "anatomy";
  row.measure = "skin relaxation per vertex per iteration, " + name;
  row.figure = skin_seconds / (s.sm.params.iterations * per_vertex) * 1e9;
  row.unit = "ns";
  row.baseline = "skinning per vertex";
  row.baseline_figure = skinning_seconds / static_cast<double>(s.rig.vertex_count()) * 1e9;
  row.target = sinew::bench::figure_at_most(40);
  row.target_source = "performance issue: elastic skin <= 40 ns per vertex per iteration";
  if (!sinew::bench::summary_row(row)) g_summary_failed = true;
}

void summary(double min_seconds) {
  std::printf("\nper-layer step cost (mean over >= %.2f s each; ratio against LBS of the same rig, same run)\n",
              min_seconds);
  std::printf("%-24s %10s %10s %10s %12s %10s %14s\n", "rig", "vertices", "LBS us", "DQS us", "muscles us", "skin us",
              "skin / LBS");
  for (Scene* s : {&arm_lbs(), &hand_asset()}) {
    if (!s->ok) {
      std::printf("%-24s skipped: %s\n", s->name.c_str(), s->error.c_str());
      continue;
    }
    const double lbs = mean_seconds([&](uint64_t i) { s->step_engine(i); }, min_seconds);
    double dqs = 0;
    // arm_dqs() is built by the condition, before the clock starts.
    if (s == &arm_lbs() && arm_dqs().ok) dqs = mean_seconds([&](uint64_t i) { arm_dqs().step_engine(i); }, min_seconds);
    // Muscles recompute only when bones move: alternate two stored poses.
    std::vector<sinew::fx::Mat34> pose_a, pose_b;
    s->step_engine(1);
    pose_a.assign(s->engine.model.begin(), s->engine.model.end());
    s->step_engine(2);
    pose_b.assign(s->engine.model.begin(), s->engine.model.end());
    const double mus =
        mean_seconds([&](uint64_t i) { muscle::muscle_step(s->mm, (i & 1) ? pose_a : pose_b, &s->ms); }, min_seconds);
    const double skin = mean_seconds([&](uint64_t) { s->step_skin(); }, min_seconds);
    char dqs_text[32] = "-";
    if (dqs > 0) std::snprintf(dqs_text, sizeof(dqs_text), "%.1f", dqs * 1e6);
    std::printf("%-24s %10u %10.1f %10s %12.2f %10.1f %14.1f\n", s->name.c_str(), s->rig.vertex_count(), lbs * 1e6,
                dqs_text, mus * 1e6, skin * 1e6, skin / lbs);
    std::printf("%-24s relaxation: %.2f ns per iteration per vertex (%u iterations, %u vertices, %u edges)\n", "",
                skin / (s->sm.params.iterations * static_cast<double>(s->sm.vertex_count)) * 1e9,
                s->sm.params.iterations, s->sm.vertex_count, static_cast<uint32_t>(s->sm.edges.size()));
    report_relaxation(s->name, skin, lbs, *s);
  }
  Scene warm("arm, 2 warm iterations", rigc::builtin_arm(rigc::SkinChoice::kLinear), arm_warm, 2);
  if (warm.ok) {
    const double lbs = mean_seconds([&](uint64_t i) { warm.step_engine(i); }, min_seconds);
    const double step = mean_seconds(
        [&](uint64_t i) {
          warm.step_engine(i);
          warm.step_muscles();
          warm.step_skin();
        },
        min_seconds);
    std::printf(
        "arm, 2 warm-started relaxations per step (LEMAN's regime): engine + muscles + skin %.1f us, "
        "%.1fx LBS alone\n",
        step * 1e6, step / lbs);
  }
  // Dynamic skin beside the static one (same run): engine + muscles + skin
  // per 1 kHz tick, and the skin step alone, against LBS and against the
  // 2-warm-iteration static skin.
  Scene dynamic("arm, dynamic skin", rigc::builtin_arm(rigc::SkinChoice::kLinear), arm_dynamic, 1);
  if (dynamic.ok && warm.ok) {
    const double lbs = mean_seconds([&](uint64_t i) { dynamic.step_engine(i); }, min_seconds);
    const auto full = [&](Scene& s) {
      return mean_seconds(
          [&](uint64_t i) {
            s.step_engine(i);
            s.step_muscles();
            s.step_skin();
          },
          min_seconds);
    };
    const double dyn = full(dynamic), stat = full(warm);
    dynamic.step_engine(7);
    dynamic.step_muscles();
    warm.step_engine(7);
    warm.step_muscles();
    const double dyn_skin = mean_seconds([&](uint64_t) { dynamic.step_skin(); }, min_seconds);
    const double stat_skin = mean_seconds([&](uint64_t) { warm.step_skin(); }, min_seconds);
    std::printf(
        "arm, dynamic skin at 1 kHz (%u substeps x %u reaction passes): engine + muscles + skin %.1f us (%.1fx LBS "
        "alone, %.2fx the 2-warm-iteration static skin); skin step %.1f us vs static %.1f us (%.2fx)\n",
        dynamic.ss.stats.substeps, dynamic.sm.solver.constraint_passes, dyn * 1e6, dyn / lbs, dyn / stat,
        dyn_skin * 1e6, stat_skin * 1e6, dyn_skin / stat_skin);
  } else if (!dynamic.ok) {
    std::printf("dynamic skin skipped: %s\n", dynamic.error.c_str());
  }
  // The dynamic skin's step per tick at the daemon's 100 Hz and at 1 kHz
  // (substeps follow the rate), against LBS of the same rig (same run) and
  // against the tick's period (its budget).
  for (uint32_t hz : {100u, 1000u}) {
    Scene& d = arm_dynamic_at(hz);
    if (!d.ok) continue;
    const double lbs = mean_seconds([&](uint64_t i) { d.step_engine(i); }, min_seconds);
    d.step_engine(7);
    d.step_muscles();
    const double skin = mean_seconds([&](uint64_t) { d.step_skin(); }, min_seconds);
    const double budget = 1.0 / hz;
    std::printf(
        "arm, dynamic skin at %u Hz (%u substeps x %u reaction passes, h omega_max %.3f): skin step %.1f us per "
        "tick, %.1fx LBS (%.1f us), %.0f%% of the %.0f ms tick\n",
        hz, d.ss.stats.substeps, d.sm.solver.constraint_passes,
        d.ss.stats.omega_max / (double(hz) * d.ss.stats.substeps), skin * 1e6, skin / lbs, lbs * 1e6,
        100 * skin / budget, budget * 1e3);
    sinew::bench::SummaryRow row;
    row.bench = "anatomy";
    row.measure = "dynamic skin step per tick, arm, " + std::to_string(hz) + " Hz";
    row.figure = skin * 1e6;
    row.unit = "us";
    row.baseline = "LBS of the arm";
    row.baseline_figure = lbs * 1e6;
    row.target = sinew::bench::figure_at_most(budget * 1e6);
    row.target_source = "the tick's period";
    if (!sinew::bench::summary_row(row)) g_summary_failed = true;
  }
  Scene tube("tube 75k", tube_75k(), bones_only, 30);
  if (!tube.ok) {
    std::printf("paper workload skipped: %s\n", tube.error.c_str());
    return;
  }
  tube.step_engine(1);
  const double paper = mean_seconds([&](uint64_t) { tube.step_skin(); }, min_seconds);
  std::printf(
      "paper workload, 30 relaxations of %u vertices: %.3f s (anatomically-based-modeling, 1997: 25 s; "
      "ratio %.0fx)\n",
      tube.sm.vertex_count, paper, 25.0 / paper);
  report_relaxation(tube.name, paper, mean_seconds([&](uint64_t i) { tube.step_engine(i); }, min_seconds), tube);
}

}  // namespace

int main(int argc, char** argv) {
  double min_seconds = 0.2;
  for (int i = 1; i < argc; ++i)
    if (std::strncmp(argv[i], "--benchmark_min_time=", 21) == 0) min_seconds = std::atof(argv[i] + 21);
  benchmark::Initialize(&argc, argv);
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  summary(min_seconds);
  return g_summary_failed ? 1 : 0;
}
