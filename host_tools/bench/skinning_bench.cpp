// Skinning throughput: sinew's fixed-point LBS and DQS beside a float Eigen
// LBS baseline on the same mesh, 4 influences per vertex, positions and
// normals, in the same run; prints vertices/s and the ratios, then fixed LBS
// and fixed DQS with each kernel side by side (the scalar specification and
// the target's vector kernel: AVX2 on x86-64, NEON for LBS on aarch64), and
// whether LBS and DQS with the kernels in use reach the target ratios. Under
// qemu-user (the aarch64 cross build) it is a smoke run: the figures measure
// the emulator.
//   sinew-bench-skinning [--benchmark_min_time=0.5]
#include <benchmark/benchmark.h>

#include <Eigen/Dense>
#include <cmath>
#include <cstdio>
#include <cstring>
#include <map>
#include <random>
#include <string>
#include <vector>

#include "host_tools/bench/common/bench_summary.hpp"
#include "host_tools/rigc/rig_spec.hpp"
#include "sim_core/engine/engine.hpp"
#include "sim_core/skin/skinning.hpp"

namespace {

namespace rigc = sinew::rigc;

constexpr int kJoints = 32;
constexpr int kInfluences = 4;
// Fixed DQS throughput wanted, as a fraction of the float LBS loop's.
constexpr double kDqsTargetRatio = 1.0;
constexpr double kLbsTargetRatio = 1.5;

// The vector LBS kernel this target builds, beside the scalar one.
constexpr sinew::skin::LbsKernel kVectorLbsKernel =
#if defined(__aarch64__)
    sinew::skin::LbsKernel::kNeon;
#else
    sinew::skin::LbsKernel::kAvx2;
#endif

// A synthetic skinned mesh: n vertices in a 2 m box, 4 random influences each
// over a 32-joint chain, both skinning methods.
rigc::RigSpec make_spec(int n, bool dual) {
  rigc::RigSpec s;
  for (int j = 0; j < kJoints; ++j) {
    rigc::JointSpec js;
    js.name = "j" + std::to_string(j);
    js.parent = j - 1;
    js.translation = {j == 0 ? 0.0 : 0.05, 0, 0};
    js.dofs = {{{0, 0, 1}, -180, 180}, {{0, 1, 0}, -180, 180}};
    s.joints.push_back(js);
    rigc::PaletteSpec p;
    p.joint = j;
    p.inverse_bind[12] = -0.05 * j;
    s.palette.push_back(p);
  }
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(-1, 1);
  for (int v = 0; v < n; ++v) {
    rigc::VertexSpec vs;
    vs.position = {u(rng) + 1, u(rng) * 0.2, u(rng) * 0.2};
    vs.normal = {u(rng), u(rng), u(rng) + 2};
    double total = 0;
    for (int k = 0; k < kInfluences; ++k) {
      const double w = 0.1 + (u(rng) + 1);
      vs.influences.push_back({static_cast<int>(rng() % kJoints), w});
      total += w;
    }
    for (auto& in : vs.influences) in.weight /= total;
    vs.dual_quaternion = dual;
    s.vertices.push_back(vs);
  }
  return s;
}

struct Fixture {
  std::vector<uint64_t> blob, rig_arena, engine_arena;
  sinew::rig::Rig rig;
  sinew::engine::Engine engine;
  std::vector<int32_t> inputs;
  int32_t exponent = 0;
};

// Fixtures are built once per (n, method) outside the timed region.
Fixture& fixture(int n, bool dual) {
  static std::map<std::pair<int, bool>, Fixture> cache;
  const auto key = std::make_pair(n, dual);
  auto it = cache.find(key);
  if (it != cache.end()) return it->second;
  Fixture& f = cache[key];
  std::vector<uint8_t> bytes;
  rigc::CompileReport report;
  std::string error;
  if (!rigc::compile_rig(make_spec(n, dual), &bytes, &report, &error)) std::abort();
  f.exponent = report.length_exponent;
  f.blob.assign(bytes.size() / 8 + 1, 0);
  std::memcpy(f.blob.data(), bytes.data(), bytes.size());
  const auto* data = reinterpret_cast<const uint8_t*>(f.blob.data());
  size_t rig_bytes = 0;
  sinew::rig::rig_validate(data, bytes.size(), &rig_bytes);
  f.rig_arena.assign(rig_bytes / 8 + 1, 0);
  sinew::rig::rig_init(data, bytes.size(), f.rig_arena.data(), f.rig_arena.size() * 8, &f.rig);
  f.engine_arena.assign(sinew::engine::engine_arena_bytes(f.rig) / 8 + 1, 0);
  sinew::engine::engine_init(f.rig, f.engine_arena.data(), f.engine_arena.size() * 8, &f.engine);
  f.inputs.assign(f.rig.input_count, 0);
  for (size_t i = 0; i < f.inputs.size(); ++i) f.inputs[i] = static_cast<int32_t>(0x05000000u * (i % 7));
  sinew::engine::engine_step(&f.engine, f.inputs);  // a posed palette
  return f;
}

void BM_FixedSkinning(benchmark::State& state, bool dual) {
  const int n = static_cast<int>(state.range(0));
  Fixture& f = fixture(n, dual);
  for (auto _ : state) {
    const uint32_t sat =
        sinew::skin::skin_vertices(f.rig, f.engine.palette, f.engine.dual, 0, f.rig.vertex_count(), f.engine.vertices);
    benchmark::DoNotOptimize(sat);
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * n);
}

// Fixed LBS with an explicit kernel (the rows above use the default one).
void BM_FixedLbsKernel(benchmark::State& state, sinew::skin::LbsKernel kernel) {
  const int n = static_cast<int>(state.range(0));
  if (!sinew::skin::lbs_kernel_supported(kernel)) {
    state.SkipWithError("kernel not supported on this CPU");
    return;
  }
  Fixture& f = fixture(n, false);
  for (auto _ : state) {
    const uint32_t sat = sinew::skin::skin_vertices(kernel, f.rig, f.engine.palette, f.engine.dual, 0,
                                                    f.rig.vertex_count(), f.engine.vertices);
    benchmark::DoNotOptimize(sat);
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * n);
}

// Fixed DQS with an explicit kernel (every vertex DQS; LBS kernel irrelevant).
void BM_FixedDqsKernel(benchmark::State& state, sinew::skin::DqsKernel kernel) {
  const int n = static_cast<int>(state.range(0));
  if (!sinew::skin::dqs_kernel_supported(kernel)) {
    state.SkipWithError("kernel not supported on this CPU");
    return;
  }
  Fixture& f = fixture(n, true);
  for (auto _ : state) {
    const uint32_t sat = sinew::skin::skin_vertices(sinew::skin::lbs_kernel_default(), kernel, f.rig, f.engine.palette,
                                                    f.engine.dual, 0, f.rig.vertex_count(), f.engine.vertices);
    benchmark::DoNotOptimize(sat);
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * n);
}

// Float baseline: the same blend-then-transform LBS in single precision with
// Eigen, SoA inputs, positions and renormalised normals.
struct FloatMesh {
  std::vector<Eigen::Matrix<float, 3, 4>> palette;
  std::vector<Eigen::Vector3f> position, normal, out_position, out_normal;
  std::vector<int> joint;
  std::vector<float> weight;
};

FloatMesh& float_mesh(int n) {
  static std::map<int, FloatMesh> cache;
  auto it = cache.find(n);
  if (it != cache.end()) return it->second;
  FloatMesh& m = cache[n];
  Fixture& f = fixture(n, false);
  const float len = std::ldexp(1.0f, f.exponent - 20);
  for (const auto& p : f.engine.palette) {
    Eigen::Matrix<float, 3, 4> mat;
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) mat(r, c) = std::ldexp(static_cast<float>(p.m[r][c]), -24);
      mat(r, 3) = static_cast<float>(p.t[r]) * len;
    }
    m.palette.push_back(mat);
  }
  for (int v = 0; v < n; ++v) {
    m.position.emplace_back(f.rig.position[0][static_cast<size_t>(v)] * len,
                            f.rig.position[1][static_cast<size_t>(v)] * len,
                            f.rig.position[2][static_cast<size_t>(v)] * len);
    m.normal.emplace_back(std::ldexp(static_cast<float>(f.rig.normal[0][static_cast<size_t>(v)]), -30),
                          std::ldexp(static_cast<float>(f.rig.normal[1][static_cast<size_t>(v)]), -30),
                          std::ldexp(static_cast<float>(f.rig.normal[2][static_cast<size_t>(v)]), -30));
    for (int k = 0; k < kInfluences; ++k) {
      m.joint.push_back(f.rig.influence_palette[static_cast<size_t>(v * kInfluences + k)]);
      m.weight.push_back(
          std::ldexp(static_cast<float>(f.rig.influence_weight[static_cast<size_t>(v * kInfluences + k)]), -30));
    }
  }
  m.out_position.resize(static_cast<size_t>(n));
  m.out_normal.resize(static_cast<size_t>(n));
  return m;
}

void BM_FloatEigenLbs(benchmark::State& state) {
  const int n = static_cast<int>(state.range(0));
  FloatMesh& m = float_mesh(n);
  for (auto _ : state) {
    for (int v = 0; v < n; ++v) {
      const size_t base = static_cast<size_t>(v) * kInfluences;
      Eigen::Matrix<float, 3, 4> b = m.weight[base] * m.palette[static_cast<size_t>(m.joint[base])];
      for (int k = 1; k < kInfluences; ++k)
        b += m.weight[base + static_cast<size_t>(k)] *
             m.palette[static_cast<size_t>(m.joint[base + static_cast<size_t>(k)])];
      m.out_position[static_cast<size_t>(v)] = b.leftCols<3>() * m.position[static_cast<size_t>(v)] + b.col(3);
      m.out_normal[static_cast<size_t>(v)] = (b.leftCols<3>() * m.normal[static_cast<size_t>(v)]).normalized();
    }
    benchmark::DoNotOptimize(m.out_position.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(state.iterations() * n);
}

// Records items/s of every run so ratios against the float baseline can be
// printed at the end of the same run.
class RatioReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) {
      const auto it = r.counters.find("items_per_second");
      if (it != r.counters.end()) rates_[r.benchmark_name()] = it->second.value;
    }
    ConsoleReporter::ReportRuns(runs);
  }
  void Print() const {
    std::printf("\nskinning throughput (4 influences, positions + normals), ratio to float Eigen LBS:\n");
    std::printf("%10s %16s %16s %16s %10s %10s\n", "vertices", "float LBS v/s", "fixed LBS v/s", "fixed DQS v/s",
                "LBS/float", "DQS/float");
    for (int n : {1000, 10000, 100000}) {
      const double fl = rate("BM_FloatEigenLbs/" + std::to_string(n));
      const double lbs = rate("BM_FixedSkinning/lbs/" + std::to_string(n));
      const double dqs = rate("BM_FixedSkinning/dqs/" + std::to_string(n));
      if (fl <= 0) continue;
      std::printf("%10d %16.3g %16.3g %16.3g %9.2fx %9.2fx\n", n, fl, lbs, dqs, lbs / fl, dqs / fl);
    }
    const sinew::skin::LbsKernel in_use = sinew::skin::lbs_kernel_default();
    std::printf("\nfixed LBS kernel in use: %s; per kernel (same outputs, word for word):\n",
                sinew::skin::lbs_kernel_name(in_use));
    const std::string vec = sinew::skin::lbs_kernel_name(kVectorLbsKernel);
    std::printf("%10s %16s %16s %16s %10s %10s %10s\n", "vertices", "float LBS v/s", "scalar LBS v/s",
                (vec + " LBS v/s").c_str(), "scalar/fl", (vec + "/fl").c_str(), (vec + "/scal").c_str());
    for (int n : {1000, 10000, 100000}) {
      const double fl = rate("BM_FloatEigenLbs/" + std::to_string(n));
      const double scalar = rate("BM_FixedLbsKernel/scalar/" + std::to_string(n));
      const double vector = rate("BM_FixedLbsKernel/" + vec + "/" + std::to_string(n));
      if (fl <= 0 || scalar <= 0) continue;
      if (vector <= 0) {
        std::printf("%10d %16.3g %16.3g %16s %9.2fx %10s %10s\n", n, fl, scalar, "n/a", scalar / fl, "n/a", "n/a");
        continue;
      }
      std::printf("%10d %16.3g %16.3g %16.3g %9.2fx %9.2fx %9.2fx\n", n, fl, scalar, vector, scalar / fl, vector / fl,
                  vector / scalar);
    }
    for (int n : {1000, 10000, 100000}) {  // the other x86 kernel, where the CPU runs it
      const double fl = rate("BM_FloatEigenLbs/" + std::to_string(n));
      const double scalar = rate("BM_FixedLbsKernel/scalar/" + std::to_string(n));
      const double avx512 = rate("BM_FixedLbsKernel/avx512/" + std::to_string(n));
      if (fl > 0 && scalar > 0 && avx512 > 0)
        std::printf("%10d avx512 LBS %.3g v/s: %.2fx float, %.2fx scalar\n", n, avx512, avx512 / fl, avx512 / scalar);
    }
    const sinew::skin::DqsKernel dqs_in_use = sinew::skin::dqs_kernel_default();
    std::printf("\nfixed DQS kernel in use: %s; per kernel (same outputs, word for word):\n",
                sinew::skin::dqs_kernel_name(dqs_in_use));
    std::printf("%10s %16s %16s %16s %10s %10s %10s\n", "vertices", "float LBS v/s", "scalar DQS v/s", "avx2 DQS v/s",
                "scalar/fl", "avx2/fl", "avx2/scal");
    double worst = -1;  // the in-use kernel's lowest ratio over the sizes
    for (int n : {1000, 10000, 100000}) {
      const double fl = rate("BM_FloatEigenLbs/" + std::to_string(n));
      const double scalar = rate("BM_FixedDqsKernel/scalar/" + std::to_string(n));
      const double avx2 = rate("BM_FixedDqsKernel/avx2/" + std::to_string(n));
      if (fl <= 0 || scalar <= 0) continue;
      const double avx512 = rate("BM_FixedDqsKernel/avx512/" + std::to_string(n));
      const double in_use = dqs_in_use == sinew::skin::DqsKernel::kAvx512 ? avx512
                            : dqs_in_use == sinew::skin::DqsKernel::kAvx2 ? avx2
                                                                          : scalar;
      if (in_use > 0 && (worst < 0 || in_use / fl < worst)) worst = in_use / fl;
      if (avx2 <= 0) {
        std::printf("%10d %16.3g %16.3g %16s %9.2fx %10s %10s\n", n, fl, scalar, "n/a", scalar / fl, "n/a", "n/a");
        continue;
      }
      std::printf("%10d %16.3g %16.3g %16.3g %9.2fx %9.2fx %9.2fx\n", n, fl, scalar, avx2, scalar / fl, avx2 / fl,
                  avx2 / scalar);
      if (avx512 > 0)
        std::printf("%10d avx512 DQS %.3g v/s: %.2fx float, %.2fx scalar, %.2fx avx2\n", n, avx512, avx512 / fl,
                    avx512 / scalar, avx512 / avx2);
    }
    if (worst >= 0)
      std::printf("target fixed DQS >= %.2fx float LBS (kernel in use, every size): %s (lowest %.2fx)\n",
                  kDqsTargetRatio, worst >= kDqsTargetRatio ? "met" : "NOT met", worst);
  }

  // The bench table's rows: 10 000 vertices, the kernels in use.
  bool Summarise() const {
    namespace sb = sinew::bench;
    const double fl = rate("BM_FloatEigenLbs/10000");
    if (fl <= 0) return true;  // filtered out: nothing to report
    bool ok = true;
    const struct {
      const char* measure;
      const char* run;
      double target;
      const char* source;
    } rows[] = {{"fixed LBS, 10k vertices, 4 influences, positions + normals", "BM_FixedSkinning/lbs/10000",
                 kLbsTargetRatio, "performance issue: LBS >= 1.5x the float loop (ozz-animation's level)"},
                {"fixed DQS, 10k vertices, 4 influences, positions + normals", "BM_FixedSkinning/dqs/10000",
                 kDqsTargetRatio, "performance issue: DQS >= 1x the float LBS loop"}};
    for (const auto& r : rows) {
      sb::SummaryRow row;
      row.bench = "skinning";
      row.measure = r.measure;
      row.figure = rate(r.run);
      row.unit = "vertices/s";
      row.baseline = "float Eigen LBS";
      row.baseline_figure = fl;
      row.target = sb::ratio_at_least(r.target);
      row.target_source = r.source;
      if (row.figure > 0) ok = sb::summary_row(row) && ok;
    }
    return ok;
  }

 private:
  double rate(const std::string& name) const {
    const auto it = rates_.find(name);
    return it == rates_.end() ? 0 : it->second;
  }
  std::map<std::string, double> rates_;
};

}  // namespace

BENCHMARK(BM_FloatEigenLbs)->Arg(1000)->Arg(10000)->Arg(100000);
BENCHMARK_CAPTURE(BM_FixedSkinning, lbs, false)->Arg(1000)->Arg(10000)->Arg(100000);
BENCHMARK_CAPTURE(BM_FixedSkinning, dqs, true)->Arg(1000)->Arg(10000)->Arg(100000);
BENCHMARK_CAPTURE(BM_FixedLbsKernel, scalar, sinew::skin::LbsKernel::kScalar)->Arg(1000)->Arg(10000)->Arg(100000);
#if defined(__aarch64__)
BENCHMARK_CAPTURE(BM_FixedLbsKernel, neon, sinew::skin::LbsKernel::kNeon)->Arg(1000)->Arg(10000)->Arg(100000);
#else
BENCHMARK_CAPTURE(BM_FixedLbsKernel, avx2, sinew::skin::LbsKernel::kAvx2)->Arg(1000)->Arg(10000)->Arg(100000);
BENCHMARK_CAPTURE(BM_FixedLbsKernel, avx512, sinew::skin::LbsKernel::kAvx512)->Arg(1000)->Arg(10000)->Arg(100000);
#endif
BENCHMARK_CAPTURE(BM_FixedDqsKernel, scalar, sinew::skin::DqsKernel::kScalar)->Arg(1000)->Arg(10000)->Arg(100000);
BENCHMARK_CAPTURE(BM_FixedDqsKernel, avx2, sinew::skin::DqsKernel::kAvx2)->Arg(1000)->Arg(10000)->Arg(100000);
BENCHMARK_CAPTURE(BM_FixedDqsKernel, avx512, sinew::skin::DqsKernel::kAvx512)->Arg(1000)->Arg(10000)->Arg(100000);

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  reporter.Print();
  const bool summarised = reporter.Summarise();
  benchmark::Shutdown();
  return summarised ? 0 : 1;
}
