// Per-frame cost of metaballs skinning against LBS (and DQS) on the same
// mesh, in the same run. Two meshes: /0 the ball count the paper used, a
// dense procedural arm tube of 31248 vertices and 500 balls (the paper:
// Armadillo 34594 vertices / 564 balls, human 24461 / 512); /1 the built-in
// arm the board runs (4192 vertices, 65 balls). Prints each frame's CPU time,
// the ratio against LBS and the share of a 1 kHz tick on this machine, and
// the cost of each newer behaviour (physical jiggle, action lines, overlap
// lists from the joints' ranges) beside LBS and the base metaballs model.
//   sinew-bench-metaballs [--benchmark_min_time=0.5]
#include <benchmark/benchmark.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <ctime>
#include <map>
#include <string>
#include <vector>

#include "host_tools/bench/common/bench_summary.hpp"
#include "host_tools/layers/metaballs/builder.hpp"
#include "host_tools/rigc/builtin_rigs.hpp"
#include "sim_core/engine/engine.hpp"
#include "sim_core/fixed/trig.hpp"
#include "sim_core/metaballs/step.hpp"

namespace {

namespace rigc = sinew::rigc;
namespace mb = sinew::metaballs;
namespace mbb = sinew::metaballs_build;

constexpr int kSegments = 48;
constexpr double kRingStep = 0.001;  // 651 rings over the 0.65 m arm: 31248 vertices

// The built-in arm's skeleton and weights on a denser tube: each dense ring
// takes the radius (interpolated) and the influences (nearest ring) of the
// built-in arm's rings, which are 5 mm apart.
rigc::RigSpec dense_arm(rigc::SkinChoice method) {
  const rigc::RigSpec base = rigc::builtin_arm(method);
  rigc::RigSpec s = base;
  s.vertices.clear();
  s.triangles.clear();
  s.primitives.clear();
  const int n = rigc::kArmRingSegments;
  const int base_rings = static_cast<int>(base.vertices.size()) / n;
  const int rings = static_cast<int>(std::floor(0.65 / kRingStep + 0.5)) + 1;
  for (int r = 0; r < rings; ++r) {
    const double x = kRingStep * r;
    const double f = x / 0.005;
    const int r0 = std::min(static_cast<int>(std::floor(f)), base_rings - 1), r1 = std::min(r0 + 1, base_rings - 1);
    const double t = f - r0;
    const double radius = (1 - t) * base.vertices[static_cast<size_t>(r0 * n)].position[1] +
                          t * base.vertices[static_cast<size_t>(r1 * n)].position[1];
    const int nearest = t < 0.5 ? r0 : r1;
    for (int k = 0; k < kSegments; ++k) {
      const sinew::fx::SinCos sc =
          sinew::fx::sin_cos(static_cast<sinew::fx::Angle>((uint64_t{1} << 32) * static_cast<uint64_t>(k) / kSegments));
      const double c = std::ldexp(static_cast<double>(sc.cos), -30), si = std::ldexp(static_cast<double>(sc.sin), -30);
      rigc::VertexSpec v = base.vertices[static_cast<size_t>(nearest * n)];
      v.position = {x, radius * c, radius * si};
      v.normal = {0, c, si};
      s.vertices.push_back(v);
    }
  }
  for (int r = 0; r + 1 < rings; ++r)
    for (int k = 0; k < kSegments; ++k) {
      const auto a = static_cast<uint32_t>(r * kSegments + k),
                 b = static_cast<uint32_t>(r * kSegments + (k + 1) % kSegments);
      s.triangles.push_back({a, a + kSegments, b});
      s.triangles.push_back({b, a + kSegments, b + kSegments});
    }
  s.primitives.push_back({0, static_cast<uint32_t>(s.vertices.size())});
  return s;
}

struct Loaded {
  std::vector<uint64_t> blob, rig_arena, engine_arena;
  sinew::rig::Rig rig;
  sinew::engine::Engine engine;
  std::vector<int32_t> inputs;
};

void load(const rigc::RigSpec& spec, Loaded* l) {
  std::vector<uint8_t> bytes;
  rigc::CompileReport report;
  std::string error;
  if (!rigc::compile_rig(spec, &bytes, &report, &error)) {
    std::fprintf(stderr, "compile: %s\n", error.c_str());
    std::abort();
  }
  l->blob.assign(bytes.size() / 8 + 1, 0);
  std::memcpy(l->blob.data(), bytes.data(), bytes.size());
  const auto* data = reinterpret_cast<const uint8_t*>(l->blob.data());
  size_t rig_bytes = 0;
  if (!sinew::rig::rig_validate(data, bytes.size(), &rig_bytes).ok()) std::abort();
  l->rig_arena.assign(rig_bytes / 8 + 1, 0);
  if (!sinew::rig::rig_init(data, bytes.size(), l->rig_arena.data(), l->rig_arena.size() * 8, &l->rig).ok())
    std::abort();
  l->engine_arena.assign(sinew::engine::engine_arena_bytes(l->rig) / 8 + 1, 0);
  if (!sinew::engine::engine_init(l->rig, l->engine_arena.data(), l->engine_arena.size() * 8, &l->engine)) std::abort();
  l->inputs.assign(l->rig.input_count, 0);
}

struct Scene {
  Loaded lbs, dqs;
  mbb::Build build;
  mb::MetaballModel model;
  std::vector<uint64_t> state_memory;
  mb::MetaballState state;
  std::vector<sinew::fx::Len> out[3];
  std::vector<sinew::skeleton::LocalPose> locals;
  std::vector<uint8_t> flags;
  std::vector<sinew::fx::Mat34> joint_model;
};

rigc::RigSpec arm(int which, rigc::SkinChoice method) {
  return which == 0 ? dense_arm(method) : rigc::builtin_arm(method);
}

// Model variants, each one new behaviour on top of the base model (per-step
// jiggle and bulging on the upper arm):
//   0 base; 1 jiggle in physical units (4 Hz, W_t 0.4 s at 1 kHz: the
//   relative-motion swing, its stretch pairs dropped); 2 base + one action
//   line (upper arm to forearm, inner side); 3 base with the overlap
//   candidates within 2.5 surface radii of the joints (the former default;
//   the base derives them from the joints' ranges, overlap_reach = 0).
constexpr int kVariants = 4;
const char* const kVariantName[kVariants] = {"metaballs", "physical jiggle", "action line", "2.5-radii overlap lists"};

Scene* make_scene(int which, int variant) {
  auto* sc = new Scene;
  load(arm(which, rigc::SkinChoice::kLinear), &sc->lbs);
  load(arm(which, rigc::SkinChoice::kDualQuaternion), &sc->dqs);
  mbb::Options o;
  if (which == 0) {
    o.target_ball_count = 500;
    o.pair_reach = 0.04;  // ~3 neighbours each side at this density
  }
  o.jiggle_frequency = 0;  // the base keeps the per-step jiggle
  if (variant == 1) {
    o.jiggle_frequency = 4;
    o.jiggle_window = 0.4;
    o.rate_hz = 1000;
  }
  if (variant == 2) {
    mbb::ActionLineSpec l;
    l.origin = "shoulder";
    l.insertion = "elbow";
    l.side[1] = 0.03;
    l.reach = 0.04;
    o.action_lines.push_back(l);
  }
  if (variant == 3) o.overlap_reach = 2.5;
  {
    o.jiggle.push_back({"shoulder", 0.3, 0.7, 0.1});
    o.bulge.push_back({"shoulder", 0.3, 0.7, "shoulder", "elbow", 0.3});
    std::string error;
    const auto t0 = std::chrono::steady_clock::now();
    if (!mbb::build(arm(which, rigc::SkinChoice::kLinear), o, &sc->build, &error)) {
      std::fprintf(stderr, "metaballs build: %s\n", error.c_str());
      std::abort();
    }
    const double build_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
    sc->model = sc->build.model();
    sc->state_memory.assign(mb::metaballs_state_bytes(sc->model) / 8 + 1, 0);
    const mb::LayerStatus st =
        mb::metaballs_init(sc->model, sc->state_memory.data(), sc->state_memory.size() * 8, &sc->state);
    if (!st.ok()) {
      std::fprintf(stderr, "metaballs init: %s\n", st.message);
      std::abort();
    }
    const uint32_t n = sc->lbs.rig.vertex_count(), j = sc->lbs.rig.joint_count();
    for (auto& o3 : sc->out) o3.assign(n, 0);
    sc->locals.resize(j);
    sc->flags.resize(j);
    sc->joint_model.resize(j);
    std::printf("%s: %s, %zu action balls, %zu overlap candidate vertices; built offline in %.2f s\n",
                kVariantName[variant], mbb::summary(sc->build).c_str(), sc->build.action_balls.size(),
                sc->build.overlap_vertices.size(), build_s);
  }
  return sc;
}

Scene& scene(int which, int variant = 0) {
  static Scene* scenes[2][kVariants] = {};
  if (scenes[which][variant] == nullptr) scenes[which][variant] = make_scene(which, variant);
  return *scenes[which][variant];
}

double cpu_ns() {
  timespec t{};
  clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e9 + static_cast<double>(t.tv_nsec);
}

// Elbow 90 degrees, twist 90, shoulder 30, moving by one step each frame so no
// frame is a repeat of the last.
void set_inputs(std::vector<int32_t>& in, uint64_t frame) {
  const int32_t wobble = static_cast<int32_t>(frame % 64) * (1 << 20);
  in[0] = (1 << 28) / 3 * 4 + wobble;  // shoulder ~30 deg
  in[3] = 1 << 30;                     // elbow 90 deg
  in[4] = (1 << 30) - wobble;          // twist ~90 deg
}

// CPU time per frame, by mesh and method (thread CPU time: steadier than
// wall time on a loaded machine).
std::map<std::string, double> g_frame_ns[2];

template <typename F>
void timed(benchmark::State& state, const char* name, F&& frame) {
  const int which = static_cast<int>(state.range(0));
  Scene& s = scene(which);
  uint64_t i = 0;
  const double t0 = cpu_ns();
  for (auto _ : state) frame(s, i++);
  const double ns = (cpu_ns() - t0) / static_cast<double>(i);
  auto& m = g_frame_ns[which];
  m[name] = ns;
  state.counters["vertices"] = s.lbs.rig.vertex_count();
  state.counters["balls"] = s.model.ball_count();
  state.counters["frame_us"] = ns / 1000.0;
  if (m.count("lbs")) state.counters["x_lbs"] = ns / m["lbs"];
}

void BM_Lbs(benchmark::State& state) {
  timed(state, "lbs", [](Scene& s, uint64_t f) {
    set_inputs(s.lbs.inputs, f);
    sinew::engine::engine_step(&s.lbs.engine, s.lbs.inputs);
    benchmark::DoNotOptimize(s.lbs.engine.vertices.position[0].data());
  });
}

void BM_Dqs(benchmark::State& state) {
  timed(state, "dqs", [](Scene& s, uint64_t f) {
    set_inputs(s.dqs.inputs, f);
    sinew::engine::engine_step(&s.dqs.engine, s.dqs.inputs);
    benchmark::DoNotOptimize(s.dqs.engine.vertices.position[0].data());
  });
}

// The skeleton (DOFs -> model transforms) then the metaballs step, with every
// stage on or only the primary deformation (eq. 1-5 without PBD, smoothing,
// overlap).
void metaballs_frame(Scene& s, uint64_t f) {
  set_inputs(s.lbs.inputs, f);
  sinew::skeleton::dofs_to_locals(s.lbs.rig, s.lbs.inputs, {}, s.locals, s.flags);
  sinew::skeleton::locals_to_model(s.lbs.rig, s.locals, s.joint_model);
  sinew::skin::SkinnedVertices out;
  for (int a = 0; a < 3; ++a) out.position[a] = s.out[a];
  if (!mb::metaballs_step(&s.state, s.joint_model, out).ok()) std::abort();
  benchmark::DoNotOptimize(s.out[0].data());
}

void BM_Metaballs(benchmark::State& state) {
  timed(state, "metaballs", [](Scene& s, uint64_t f) {
    s.state.features = {};
    metaballs_frame(s, f);
  });
}

void BM_MetaballsPrimaryOnly(benchmark::State& state) {
  timed(state, "metaballs-primary", [](Scene& s, uint64_t f) {
    s.state.features.pbd = s.state.features.smoothing = s.state.features.overlap = false;
    metaballs_frame(s, f);
  });
  scene(static_cast<int>(state.range(0))).state.features = {};
}

// Each new behaviour's model, every stage on; compared with LBS and the
// base metaballs model in the summary.
std::map<std::string, double> g_variant_ns[2];

void BM_MetaballsVariant(benchmark::State& state) {
  const int which = static_cast<int>(state.range(0)), variant = static_cast<int>(state.range(1));
  Scene& s = scene(which, variant);
  s.state.features = {};
  uint64_t i = 0;
  const double t0 = cpu_ns();
  for (auto _ : state) metaballs_frame(s, i++);
  const double ns = (cpu_ns() - t0) / static_cast<double>(i);
  g_variant_ns[which][kVariantName[variant]] = ns;
  state.counters["frame_us"] = ns / 1000.0;
  state.SetLabel(kVariantName[variant]);
}

BENCHMARK(BM_Lbs)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Dqs)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_Metaballs)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MetaballsPrimaryOnly)->Arg(0)->Arg(1)->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_MetaballsVariant)->ArgsProduct({{0, 1}, {0, 1, 2, 3}})->Unit(benchmark::kMicrosecond);

}  // namespace

namespace sb = sinew::bench;

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  for (int which = 0; which < 2; ++which) {
    const auto& m = g_frame_ns[which];
    if (!m.count("lbs") || !m.count("metaballs")) continue;
    std::printf("summary: %u vertices, %u balls; CPU per frame LBS %.1f us", scene(which).lbs.rig.vertex_count(),
                scene(which).model.ball_count(), m.at("lbs") / 1000);
    if (m.count("dqs")) std::printf(", DQS %.1f us (%.2fx LBS)", m.at("dqs") / 1000, m.at("dqs") / m.at("lbs"));
    std::printf(
        ", metaballs %.1f us (%.2fx LBS, %.0f%% of a 1 kHz tick on "
        "this machine)",
        m.at("metaballs") / 1000, m.at("metaballs") / m.at("lbs"), m.at("metaballs") / 1e4);
    if (m.count("metaballs-primary"))
      std::printf(", primary deformation only %.1f us (%.2fx LBS)", m.at("metaballs-primary") / 1000,
                  m.at("metaballs-primary") / m.at("lbs"));
    std::printf("\n");
    const auto& v = g_variant_ns[which];
    if (v.count(kVariantName[0]))
      for (int k = 1; k < kVariants; ++k)
        if (v.count(kVariantName[k]))
          std::printf("  new behaviour: %s %.1f us (%.2fx LBS, %+.1f us against the base model's %.1f us)\n",
                      kVariantName[k], v.at(kVariantName[k]) / 1000, v.at(kVariantName[k]) / m.at("lbs"),
                      (v.at(kVariantName[k]) - v.at(kVariantName[0])) / 1000, v.at(kVariantName[0]) / 1000);
    char measure[96];
    std::snprintf(measure, sizeof(measure), "metaballs frame, %u vertices, %u balls",
                  scene(which).lbs.rig.vertex_count(), scene(which).model.ball_count());
    sb::SummaryRow row;
    row.bench = "metaballs";
    row.measure = measure;
    row.figure = m.at("metaballs") / 1000;
    row.unit = "us";
    row.baseline = "LBS engine step";
    row.baseline_figure = m.at("lbs") / 1000;
    row.target = sb::ratio_at_most(1.5);
    row.target_source = "performance issue: metaballs <= 1.5x LBS";
    if (!sb::summary_row(row)) return 1;
  }
  return 0;
}
