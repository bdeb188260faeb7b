// Per-step cost of the anatomy layers beside skinning, on the built-in arm
// and on the largest shared asset (tests/data/generic-hand_left.glb, skin
// layer only: it has no muscles), the relaxation cost per iteration per
// vertex, and the anatomically-based paper's workload (30 relaxations of
// 75 000 vertices: 25 s in 1997) measured on a 75 000-vertex tube, and the
// arm's dynamic skin (LEMAN §3) per tick at 100 Hz and 1 kHz against LBS
// and against the tick's period; primitive_sample and primitive_push_out
// on the exact integer kernel (p = 2) beside the general superquadric one
// (p = 2 and p_xy = 3, p_z = 2.5), same run.
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
#include "sim_core/muscle/primitive.hpp"
#include "sim_core/muscle/superquadric.hpp"

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
    muscle::LayerStatus st = muscle::muscle_init(mm, muscle_memory.data(), muscle_memory.size() * 8, &ms);
    if (st.ok()) st = es::skin_init(sm, skin_memory.data(), skin_memory.size() * 8, &ss);
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

// The arm with the dynamic skin (LEMAN §3) at its defaults: one implicit
// step a tick, 3 Gauss-Seidel sweeps (§6.11), bend and Platt-Barr reactions.
ab::AnatomySpec arm_dynamic(const rigc::RigSpec& spec) {
  ab::AnatomySpec a = ab::arm_anatomy(spec);
  a.skin.solver.dynamic = true;
  return a;
}

// The same with the explicit integrator: 1 kHz substeps, 3 reaction passes
// each (the option the relaxation replaced as the default).
ab::AnatomySpec arm_dynamic_explicit(const rigc::RigSpec& spec) {
  ab::AnatomySpec a = arm_dynamic(spec);
  a.skin.solver.relaxation = false;
  return a;
}

// The same with both bellies general superquadrics (p_xy 3, p_z 2.5).
ab::AnatomySpec arm_dynamic_superquadric(const rigc::RigSpec& spec) {
  ab::AnatomySpec a = arm_dynamic(spec);
  for (ab::PrimitiveSpec& p : a.primitives) {
    p.exponent = 3;
    p.exponent_z = 2.5;
  }
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

// The explicit one at 100 Hz: the substep rate stays 1 kHz, so a tick
// takes 10 substeps (max_substeps raised for rigs that ask for more).
ab::AnatomySpec arm_dynamic_explicit_100hz(const rigc::RigSpec& spec) {
  ab::AnatomySpec a = arm_dynamic_explicit(spec);
  a.skin.solver.max_substeps = 64;
  return a;
}

Scene& arm_dynamic_at(uint32_t hz) {
  static Scene s100("arm, dynamic skin (relaxation), 100 Hz", rigc::builtin_arm(rigc::SkinChoice::kLinear), arm_dynamic,
                    1);
  static Scene s1k("arm, dynamic skin (relaxation), 1 kHz", rigc::builtin_arm(rigc::SkinChoice::kLinear), arm_dynamic,
                   1);
  s100.tick_hz = 100;
  return hz == 100 ? s100 : s1k;
}
Scene& arm_explicit_at(uint32_t hz) {
  static Scene s100("arm, dynamic skin (explicit), 100 Hz", rigc::builtin_arm(rigc::SkinChoice::kLinear),
                    arm_dynamic_explicit_100hz, 1);
  static Scene s1k("arm, dynamic skin (explicit), 1 kHz", rigc::builtin_arm(rigc::SkinChoice::kLinear),
                   arm_dynamic_explicit, 1);
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
BENCHMARK_CAPTURE(run_skin, arm_explicit_100hz, arm_explicit_at(100));
BENCHMARK_CAPTURE(run_skin, arm_explicit_1khz, arm_explicit_at(1000));
BENCHMARK_CAPTURE(run_engine, hand_asset_skinning, hand_asset());
BENCHMARK_CAPTURE(run_skin, hand_asset_30_iterations, hand_asset());

// A superellipsoid of half-extents (0.3, 0.2, 0.5) units and 1024 points
// in and around it (|q_i| < 1.1), fixed seed: the primitive kernels' cost.
struct PrimitiveCase {
  muscle::PrimitiveFrame frame;
  std::vector<sinew::fx::Vec3> points;
  PrimitiveCase(double pxy, double pz, bool exact) {
    frame.kind = static_cast<uint8_t>(muscle::PrimitiveKind::kSuperellipsoid);
    frame.active = 1;
    frame.axis[0] = {sinew::fx::kUnitOne, 0, 0};
    frame.axis[1] = {0, sinew::fx::kUnitOne, 0};
    frame.axis[2] = {0, 0, sinew::fx::kUnitOne};
    const double extent[3] = {0.3, 0.2, 0.5};
    for (int c = 0; c < 3; ++c) frame.extent[c] = static_cast<int32_t>(extent[c] * 1048576);
    frame.exponent = exact ? static_cast<uint8_t>(pxy) : 0;
    frame.superquadric.power_xy = static_cast<int32_t>(pxy * 65536);
    frame.superquadric.power_z = static_cast<int32_t>(pz * 65536);
    muscle::superquadric_prepare(&frame);
    uint64_t x = 0x9E3779B97F4A7C15u;
    const auto next = [&] {  // xorshift64*, uniform in [-1.1, 1.1)
      x ^= x >> 12, x ^= x << 25, x ^= x >> 27;
      return (static_cast<double>((x * 0x2545F4914F6CDD1Du) >> 11) / 9007199254740992.0 * 2 - 1) * 1.1;
    };
    for (int i = 0; i < 1024; ++i)
      points.push_back({static_cast<int32_t>(next() * frame.extent[0]), static_cast<int32_t>(next() * frame.extent[1]),
                        static_cast<int32_t>(next() * frame.extent[2])});
  }
};
PrimitiveCase& exact_p2() {
  static PrimitiveCase c(2, 2, true);
  return c;
}
PrimitiveCase& general_p2() {
  static PrimitiveCase c(2, 2, false);
  return c;
}
PrimitiveCase& general_3_25() {
  static PrimitiveCase c(3, 2.5, false);
  return c;
}

int64_t sample_all(const PrimitiveCase& c) {
  int64_t sum = 0;
  for (const sinew::fx::Vec3& p : c.points) sum += muscle::primitive_sample(c.frame, p).value;
  return sum;
}
int64_t push_all(const PrimitiveCase& c) {
  int64_t sum = 0;
  for (const sinew::fx::Vec3& p : c.points) sum += muscle::primitive_push_out(c.frame, p, {0, 0, 1 << 30}, 3).x;
  return sum;
}
void run_primitive_sample(benchmark::State& state, PrimitiveCase& c) {
  for (auto _ : state) benchmark::DoNotOptimize(sample_all(c));
  state.counters["per_point"] =
      benchmark::Counter(static_cast<double>(state.iterations()) * static_cast<double>(c.points.size()),
                         benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
}
void run_primitive_push_out(benchmark::State& state, PrimitiveCase& c) {
  for (auto _ : state) benchmark::DoNotOptimize(push_all(c));
}
BENCHMARK_CAPTURE(run_primitive_sample, exact_p2, exact_p2());
BENCHMARK_CAPTURE(run_primitive_sample, general_p2, general_p2());
BENCHMARK_CAPTURE(run_primitive_sample, general_pxy3_pz2_5, general_3_25());
BENCHMARK_CAPTURE(run_primitive_push_out, exact_p2, exact_p2());
BENCHMARK_CAPTURE(run_primitive_push_out, general_pxy3_pz2_5, general_3_25());

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

// The general superquadric kernel against the exact one, per point (same run).
void primitive_summary(double min_seconds) {
  const auto per_point = [&](int64_t (*f)(const PrimitiveCase&), PrimitiveCase& c) {
    int64_t sink = 0;
    const double t = mean_seconds([&](uint64_t) { sink += f(c); }, min_seconds);
    benchmark::DoNotOptimize(sink);
    return t / static_cast<double>(c.points.size()) * 1e9;
  };
  const double exact = per_point(sample_all, exact_p2()), general2 = per_point(sample_all, general_p2()),
               general = per_point(sample_all, general_3_25());
  std::printf(
      "primitive_sample per point: exact kernel p = 2 %.1f ns; general kernel p = 2 %.1f ns (%.1fx), p_xy 3 p_z 2.5 "
      "%.1f ns (%.1fx)\n",
      exact, general2, general2 / exact, general, general / exact);
  const double push_exact = per_point(push_all, exact_p2()), push_general = per_point(push_all, general_3_25());
  std::printf(
      "primitive_push_out (3 Newton steps) per point: exact kernel p = 2 %.1f ns; general p_xy 3 p_z 2.5 %.1f ns "
      "(%.1fx)\n",
      push_exact, push_general, push_general / push_exact);
  // The arm's dynamic skin at 1 kHz with its bellies exact (p 4 and 2) and
  // general (3, 2.5), same poses: the reaction passes' share of the change.
  Scene& exact_arm = arm_dynamic_at(1000);
  Scene general_arm("arm, dynamic skin, general bellies", rigc::builtin_arm(rigc::SkinChoice::kLinear),
                    arm_dynamic_superquadric, 1);
  if (!exact_arm.ok || !general_arm.ok) return;
  const auto skin_tick = [&](Scene& s, uint32_t* reactions) {
    uint32_t count = 0;
    const double t = mean_seconds(
        [&](uint64_t i) {
          s.step_engine(i);
          s.step_muscles();
          s.step_skin();
          count += s.ss.stats.reactions;
        },
        min_seconds);
    *reactions = count;
    return t;
  };
  uint32_t exact_reactions = 0, general_reactions = 0;
  const double exact_tick = skin_tick(exact_arm, &exact_reactions);
  const double general_tick = skin_tick(general_arm, &general_reactions);
  std::printf(
      "arm, dynamic skin at 1 kHz, engine + muscles + skin: bellies p 4 and 2 (exact kernel) %.1f us, bellies p_xy 3 "
      "p_z 2.5 (general kernel) %.1f us (%.2fx; %u and %u reactions over the runs)\n",
      exact_tick * 1e6, general_tick * 1e6, general_tick / exact_tick, exact_reactions, general_reactions);
}

void summary(double min_seconds) {
  primitive_summary(min_seconds);
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
        "arm, dynamic skin at %u Hz (relaxation: 1 step x %u sweeps, h omega_max %.3f): skin step %.1f us per "
        "tick, %.1fx LBS (%.1f us), %.0f%% of the %.0f ms tick\n",
        hz, unsigned{d.sm.surface.relaxation_iterations}, d.ss.stats.omega_max / double(hz), skin * 1e6, skin / lbs,
        lbs * 1e6, 100 * skin / budget, budget * 1e3);
    // The explicit integrator, same run: substeps and projections.
    Scene& e = arm_explicit_at(hz);
    if (e.ok) {
      e.step_engine(7);
      e.step_muscles();
      const double explicit_skin = mean_seconds([&](uint64_t) { e.step_skin(); }, min_seconds);
      std::printf(
          "arm, dynamic skin at %u Hz (explicit: %u substeps x %u reaction passes): skin step %.1f us, "
          "relaxation / explicit %.2f\n",
          hz, e.ss.stats.substeps, e.sm.solver.constraint_passes, explicit_skin * 1e6, skin / explicit_skin);
    }
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
