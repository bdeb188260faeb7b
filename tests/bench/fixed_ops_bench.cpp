// sim_core's fixed-point scalar operations beside their float equivalents, in
// one run, followed by a table of fixed/float real time per item computed
// from that same run.
//
//   cmake --preset release && cmake --build --preset release --target sinew-bench-fixed
//   build/release/tests/bench/sinew-bench-fixed --benchmark_min_time=0.5
//
// (Debian's Google Benchmark 1.7 takes --benchmark_min_time in plain seconds;
// --benchmark_filter=sin_cos selects one pair; the ratio table lists the
// pairs that ran.) Each iteration maps kBatch precomputed inputs to an output
// array, so nothing folds to a constant; inputs of a pair hold the same
// values. The fixed ops are out-of-line calls into sinew_core, as the engine
// uses them, while the compiler is free to inline and vectorise the float
// loops: the ratios are what each costs in a plain loop, not per-instruction.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <cstdio>
#include <map>
#include <numbers>
#include <random>
#include <string>
#include <vector>

#include "float_ops.hpp"
#include "hal/units/float_to_fixed.hpp"
#include "sim_core/fixed/mat34.hpp"
#include "sim_core/fixed/quat.hpp"
#include "sim_core/fixed/sqrt.hpp"
#include "sim_core/fixed/trig.hpp"

namespace {

namespace fx = sinew::fx;
namespace units = sinew::units;
using sinew::bench::Mat34F;
using sinew::bench::QuatF;
using sinew::bench::Vec3F;

constexpr size_t kBatch = 4096;

// Every input set, built once before any benchmark runs.
struct Inputs {
  std::vector<fx::Angle> angle;
  std::vector<float> angle_rad;
  std::vector<int32_t> y, x;  // atan2 operands, mixed magnitudes
  std::vector<float> yf, xf;
  std::vector<uint64_t> square;  // isqrt operands, every magnitude
  std::vector<float> square_f;
  std::vector<uint64_t> norm_q60;  // rsqrt operands in [2^58, 2^63)
  std::vector<float> norm_f;
  std::vector<fx::Quat> qa, qb, q_raw;  // unit pairs; raw: not normalised
  std::vector<QuatF> qa_f, qb_f, q_raw_f;
  std::vector<fx::Mat34> mat;
  std::vector<Mat34F> mat_f;
  std::vector<fx::Vec3> point;
  std::vector<Vec3F> point_f;
};

int32_t unit(double v) { return units::to_unit(v).value; }
int32_t lin(double v) { return units::to_lin(v).value; }
int32_t len(double v) { return units::to_len(v, 0).value; }

QuatF to_float(const fx::Quat& q) {
  return {static_cast<float>(units::unit_to_double(q.w)), static_cast<float>(units::unit_to_double(q.x)),
          static_cast<float>(units::unit_to_double(q.y)), static_cast<float>(units::unit_to_double(q.z))};
}

fx::Quat random_unit_quat(std::mt19937_64& rng) {
  std::normal_distribution<double> n;
  const double w = n(rng), x = n(rng), y = n(rng), z = n(rng);
  const double s = 1.0 / std::sqrt(w * w + x * x + y * y + z * z);
  return {unit(w * s), unit(x * s), unit(y * s), unit(z * s)};
}

Inputs make_inputs() {
  Inputs in;
  std::mt19937_64 rng(2024);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (size_t i = 0; i < kBatch; ++i) {
    const double rad = u(rng) * std::numbers::pi;
    in.angle.push_back(units::angle_from_radians(rad).value);
    in.angle_rad.push_back(static_cast<float>(rad));

    const auto y = static_cast<int32_t>(static_cast<uint32_t>(rng())) >> (rng() % 31);
    const auto x = static_cast<int32_t>(static_cast<uint32_t>(rng())) >> (rng() % 31);
    in.y.push_back(y);
    in.x.push_back(x);
    in.yf.push_back(static_cast<float>(y));
    in.xf.push_back(static_cast<float>(x));

    const uint64_t sq = rng() >> (rng() % 64);
    in.square.push_back(sq);
    in.square_f.push_back(static_cast<float>(sq));

    const uint64_t n = (uint64_t{1} << 58) + rng() % ((uint64_t{1} << 63) - (uint64_t{1} << 58));
    in.norm_q60.push_back(n);
    in.norm_f.push_back(static_cast<float>(std::ldexp(static_cast<double>(n), -60)));

    in.qa.push_back(random_unit_quat(rng));
    in.qb.push_back(random_unit_quat(rng));
    in.q_raw.push_back({unit(0.5 * u(rng)), unit(0.5 * u(rng)), unit(0.5 * u(rng)), unit(0.5 * u(rng))});
    in.qa_f.push_back(to_float(in.qa.back()));
    in.qb_f.push_back(to_float(in.qb.back()));
    in.q_raw_f.push_back(to_float(in.q_raw.back()));

    const fx::Vec3 t{len(2 * u(rng)), len(2 * u(rng)), len(2 * u(rng))};
    const fx::Vec3 s{lin(1 + 0.5 * u(rng)), lin(1 + 0.5 * u(rng)), lin(1 + 0.5 * u(rng))};
    const fx::Mat34 m = fx::mat34_from_trs(t, random_unit_quat(rng), s);
    Mat34F mf{};
    for (int r = 0; r < 3; ++r) {
      for (int c = 0; c < 3; ++c) mf.m[r][c] = static_cast<float>(units::lin_to_double(m.m[r][c]));
      mf.t[r] = static_cast<float>(units::len_to_double(m.t[r], 0));
    }
    in.mat.push_back(m);
    in.mat_f.push_back(mf);

    const fx::Vec3 p{len(u(rng)), len(u(rng)), len(u(rng))};
    in.point.push_back(p);
    in.point_f.push_back({static_cast<float>(units::len_to_double(p.x, 0)),
                          static_cast<float>(units::len_to_double(p.y, 0)),
                          static_cast<float>(units::len_to_double(p.z, 0))});
  }
  return in;
}

const Inputs& inputs() {
  static const Inputs in = make_inputs();
  return in;
}

// Runs `op(i)` for every input index into `out`, kBatch items per iteration.
template <typename Out, typename Op>
void run_batch(benchmark::State& state, std::vector<Out>& out, Op op) {
  out.resize(kBatch);
  for (auto _ : state) {
    for (size_t i = 0; i < kBatch; ++i) out[i] = op(i);
    benchmark::DoNotOptimize(out.data());
    benchmark::ClobberMemory();
  }
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations()) * static_cast<int64_t>(kBatch));
}

void sin_cos_fixed(benchmark::State& state) {
  const Inputs& in = inputs();
  std::vector<fx::SinCos> out;
  run_batch(state, out, [&](size_t i) { return fx::sin_cos(in.angle[i]); });
}

void sin_cos_float(benchmark::State& state) {
  const Inputs& in = inputs();
  std::vector<Vec3F> out;  // x = sin, y = cos
  run_batch(state, out, [&](size_t i) { return Vec3F{std::sin(in.angle_rad[i]), std::cos(in.angle_rad[i]), 0}; });
}

void atan2_fixed(benchmark::State& state) {
  const Inputs& in = inputs();
  std::vector<fx::Angle> out;
  run_batch(state, out, [&](size_t i) { return fx::atan2_angle(in.y[i], in.x[i]); });
}

void atan2_float(benchmark::State& state) {
  const Inputs& in = inputs();
  std::vector<float> out;
  run_batch(state, out, [&](size_t i) { return std::atan2(in.yf[i], in.xf[i]); });
}

void sqrt_fixed(benchmark::State& state) {
  const Inputs& in = inputs();
  std::vector<uint32_t> out;
  run_batch(state, out, [&](size_t i) { return fx::isqrt_u64(in.square[i]); });
}

void sqrt_float(benchmark::State& state) {
  const Inputs& in = inputs();
  std::vector<float> out;
  run_batch(state, out, [&](size_t i) { return std::sqrt(in.square_f[i]); });
}

void rsqrt_fixed(benchmark::State& state) {
  const Inputs& in = inputs();
  std::vector<fx::Unit> out;
  run_batch(state, out, [&](size_t i) { return fx::rsqrt_q60(in.norm_q60[i]); });
}

void rsqrt_float(benchmark::State& state) {
  const Inputs& in = inputs();
  std::vector<float> out;
  run_batch(state, out, [&](size_t i) { return 1.0f / std::sqrt(in.norm_f[i]); });
}

void quat_mul_fixed(benchmark::State& state) {
  const Inputs& in = inputs();
  std::vector<fx::Quat> out;
  run_batch(state, out, [&](size_t i) { return fx::mul(in.qa[i], in.qb[i]); });
}

void quat_mul_float(benchmark::State& state) {
  const Inputs& in = inputs();
  std::vector<QuatF> out;
  run_batch(state, out, [&](size_t i) { return sinew::bench::mul(in.qa_f[i], in.qb_f[i]); });
}

void transform_fixed(benchmark::State& state) {
  const Inputs& in = inputs();
  std::vector<fx::Vec3> out;
  run_batch(state, out, [&](size_t i) { return fx::transform_point(in.mat[i], in.point[i]); });
}

void transform_float(benchmark::State& state) {
  const Inputs& in = inputs();
  std::vector<Vec3F> out;
  run_batch(state, out, [&](size_t i) { return sinew::bench::transform_point(in.mat_f[i], in.point_f[i]); });
}

void normalize_fixed(benchmark::State& state) {
  const Inputs& in = inputs();
  std::vector<fx::Quat> out;
  run_batch(state, out, [&](size_t i) {
    fx::Quat q = in.q_raw[i];
    fx::normalize(&q);
    return q;
  });
}

void normalize_float(benchmark::State& state) {
  const Inputs& in = inputs();
  std::vector<QuatF> out;
  run_batch(state, out, [&](size_t i) {
    QuatF q = in.q_raw_f[i];
    sinew::bench::normalize(&q);
    return q;
  });
}

struct Pair {
  const char* name;  // benchmarks <name>/fixed and <name>/float
  const char* fixed_op;
  const char* float_op;
  void (*fixed)(benchmark::State&);
  void (*single)(benchmark::State&);
};

const Pair kPairs[] = {
    {"sin_cos", "fx::sin_cos", "std::sin + std::cos", sin_cos_fixed, sin_cos_float},
    {"atan2", "fx::atan2_angle", "std::atan2", atan2_fixed, atan2_float},
    {"sqrt", "fx::isqrt_u64", "std::sqrt", sqrt_fixed, sqrt_float},
    {"rsqrt", "fx::rsqrt_q60", "1 / std::sqrt", rsqrt_fixed, rsqrt_float},
    {"quat_mul", "fx::mul (Quat)", "float quat mul", quat_mul_fixed, quat_mul_float},
    {"transform_point", "fx::transform_point", "float 3x4 transform", transform_fixed, transform_float},
    {"quat_normalize", "fx::normalize (Quat)", "float quat normalize", normalize_fixed, normalize_float},
};

std::string fixed_name(const Pair& p) { return std::string(p.name) + "/fixed"; }
std::string float_name(const Pair& p) { return std::string(p.name) + "/float"; }

// The console output, plus each run's real time per item (the fastest when
// repeated) for the ratio table printed after the run.
class RatioReporter : public benchmark::ConsoleReporter {
 public:
  void ReportRuns(const std::vector<Run>& runs) override {
    for (const Run& r : runs) {
      if (r.run_type != Run::RT_Iteration || r.error_occurred || r.iterations <= 0) continue;
      const double ns = r.real_accumulated_time * 1e9 / static_cast<double>(r.iterations) / static_cast<double>(kBatch);
      const auto [it, inserted] = ns_per_item_.try_emplace(r.benchmark_name(), ns);
      if (!inserted) it->second = std::min(it->second, ns);
    }
    ConsoleReporter::ReportRuns(runs);
  }

  void print_ratios() const {
    std::printf("\nfixed-point vs float, real time per item, this run (%zu items per iteration):\n", kBatch);
    std::printf("%-22s %-22s %10s %10s %12s\n", "fixed op", "float op", "fixed ns", "float ns", "fixed/float");
    for (const Pair& p : kPairs) {
      const auto f = ns_per_item_.find(fixed_name(p));
      const auto s = ns_per_item_.find(float_name(p));
      if (f == ns_per_item_.end() || s == ns_per_item_.end()) continue;
      std::printf("%-22s %-22s %10.2f %10.2f %11.2fx\n", p.fixed_op, p.float_op, f->second, s->second,
                  f->second / s->second);
    }
  }

 private:
  std::map<std::string, double> ns_per_item_;
};

}  // namespace

int main(int argc, char** argv) {
  inputs();  // outside every timed region
  for (const Pair& p : kPairs) {
    benchmark::RegisterBenchmark(fixed_name(p).c_str(), p.fixed);
    benchmark::RegisterBenchmark(float_name(p).c_str(), p.single);
  }
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  RatioReporter reporter;
  benchmark::RunSpecifiedBenchmarks(&reporter);
  reporter.print_ratios();
  benchmark::Shutdown();
  return 0;
}
