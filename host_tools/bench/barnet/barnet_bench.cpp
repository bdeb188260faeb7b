// Per-step cost of the bar-net layer on the built-in arm, beside the smooth
// skinning (LBS and DQS engine steps) of the same rig, measured in the same
// run; and how the step scales with the net's size. Prints the ratios as
// counters (x_lbs: this benchmark's time per step / the LBS engine step) and
// a final summary table.
#include <benchmark/benchmark.h>

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <span>
#include <string>
#include <vector>

#include "host_tools/bench/common/bench_summary.hpp"
#include "host_tools/layers/barnet/arm_session.hpp"
#include "host_tools/layers/barnet/muscle_net.hpp"
#include "host_tools/layers/barnet/wrinkle_net.hpp"

namespace bn = sinew::barnet;
namespace lb = sinew::layers::barnet;

namespace {

lb::ArmNetOptions net_options(int segments, bool q_input = false, bool profile_order = true) {
  lb::ArmNetOptions o;
  o.segments = segments;
  o.q_input = q_input;
  o.profile_order = profile_order;
  return o;
}

// Force-density scales the run-time refactor benchmarks cycle through (Q16.16).
int32_t q_scale(int64_t i) { return static_cast<int32_t>((1 << 15) + (i % 7) * (1 << 14)); }

// Median seconds per call of f over `reps` batches of `n` calls.
template <typename F>
double median_seconds(F&& f, int n, int reps = 7) {
  std::vector<double> t;
  for (int r = 0; r < reps; ++r) {
    const auto a = std::chrono::steady_clock::now();
    for (int i = 0; i < n; ++i) f(i);
    t.push_back(std::chrono::duration<double>(std::chrono::steady_clock::now() - a).count() / n);
  }
  std::sort(t.begin(), t.end());
  return t[t.size() / 2];
}

double lbs_baseline() {
  static const double seconds = [] {
    lb::ArmSession s(sinew::rigc::SkinChoice::kLinear);
    const size_t elbow = static_cast<size_t>(s.input("elbow.0"));
    return median_seconds(
        [&](int i) {
          s.inputs()[elbow] = lb::degrees_to_angle(i % 150);
          benchmark::DoNotOptimize(s.engine_step());
        },
        200);
  }();
  return seconds;
}

void set_elbow(lb::ArmSession& s, int64_t i) {
  s.inputs()[static_cast<size_t>(s.input("elbow.0"))] = lb::degrees_to_angle(static_cast<double>(i % 150));
}

void report(benchmark::State& state, size_t items) {
  // (iterations x baseline) / elapsed, inverted: time per step / LBS step.
  state.counters["x_lbs"] = benchmark::Counter(static_cast<double>(state.iterations()) * lbs_baseline(),
                                               benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  state.SetItemsProcessed(static_cast<int64_t>(state.iterations() * items));
}

void BM_EngineStep(benchmark::State& state) {
  lb::ArmSession s(state.range(0) == 0 ? sinew::rigc::SkinChoice::kLinear : sinew::rigc::SkinChoice::kDualQuaternion);
  int64_t i = 0;
  for (auto _ : state) {
    set_elbow(s, i++);
    benchmark::DoNotOptimize(s.engine_step());
  }
  report(state, s.rig().vertex_count());
  state.SetLabel(state.range(0) == 0 ? "arm LBS (baseline)" : "arm DQS");
}

// One bar-net step loop, shared by the benchmarks and the summary: the
// bones from one engine step at 90 degrees, then bar-net steps with the
// elbow angle varying (the loads' activation) and, for a net whose q follows
// an input, that input changing every step (D re-assembled and
// re-factorised each time: the fixed cost of run-time force densities).
class BarnetStepLoop {
 public:
  explicit BarnetStepLoop(const lb::ArmNetOptions& options)
      : session_(sinew::rigc::SkinChoice::kLinear, options), q_input_(options.q_input) {
    prepare();
  }
  explicit BarnetStepLoop(const lb::ArmSession::NetBuilder& net) : session_(sinew::rigc::SkinChoice::kLinear, net) {
    prepare();
  }
  bool ok() const { return session_.ok(); }
  const std::string& error() const { return session_.error(); }
  lb::ArmSession& session() { return session_; }

  // Step i of the loop; returns the step's error code.
  bn::LayerError step(int64_t i) {
    const int32_t external[1] = {q_scale(i)};
    angles_[elbow_] = lb::degrees_to_angle(static_cast<double>(i % 150));
    const std::span<const int32_t> ext = q_input_ ? std::span<const int32_t>(external) : std::span<const int32_t>();
    return bn::barnet_step(&session_.state(), {session_.engine().model, angles_, ext}, session_.outputs()).error;
  }

 private:
  void prepare() {
    if (!session_.ok()) return;
    elbow_ = static_cast<size_t>(session_.input("elbow.0"));
    set_elbow(session_, 90);
    session_.engine_step();
    angles_ = session_.inputs();
  }
  lb::ArmSession session_;
  bool q_input_ = false;
  size_t elbow_ = 0;
  std::vector<int32_t> angles_;
};

void run_loop(benchmark::State& state, BarnetStepLoop& loop, const char* label) {
  if (!loop.ok()) return state.SkipWithError(loop.error().c_str());
  int64_t i = 0;
  for (auto _ : state) benchmark::DoNotOptimize(loop.step(i++));
  lb::ArmSession& s = loop.session();
  report(state, s.model().wrap.size());
  char text[200];
  std::snprintf(text, sizeof(text), "%zu nodes (%u free), %zu bars, profile %u, %zu wrapped vertices%s",
                s.model().nodes.size(), s.state().free_count, s.model().bars.size(), s.state().profile,
                s.model().wrap.size(), label);
  state.SetLabel(text);
}

// The bar-net step alone.
void BM_BarnetStep(benchmark::State& state) {
  BarnetStepLoop loop(net_options(static_cast<int>(state.range(0))));
  run_loop(state, loop, "");
}

// The same step with every bar's q from an input that changes every step.
void BM_BarnetStepRefactor(benchmark::State& state) {
  BarnetStepLoop loop(net_options(static_cast<int>(state.range(0)), true));
  run_loop(state, loop, ", q from an input (refactor)");
}

// Both with the free nodes in the spec's order (the builder's default is
// reverse Cuthill-McKee, a smaller profile).
void BM_BarnetStepSpecOrder(benchmark::State& state) {
  BarnetStepLoop loop(net_options(static_cast<int>(state.range(0)), state.range(1) != 0, false));
  run_loop(state, loop, state.range(1) != 0 ? ", spec order, q from an input (refactor)" : ", spec order");
}

// The paper's Figure 3 (biceps/triceps, 12 free nodes) and Figure 6
// (wrinkles on the fine mesh) nets.
void BM_BarnetFigureNet(benchmark::State& state) {
  BarnetStepLoop loop(
      state.range(0) == 3
          ? lb::ArmSession::NetBuilder([](const sinew::rigc::RigSpec& arm, lb::NetSpec* net, std::string* e) {
              return lb::arm_muscle_net(arm, {}, net, e);
            })
          : lb::ArmSession::NetBuilder([](const sinew::rigc::RigSpec& arm, lb::NetSpec* net, std::string* e) {
              return lb::arm_wrinkle_net(arm, {}, net, e);
            }));
  run_loop(state, loop, state.range(0) == 3 ? ", figure 3 net" : ", figure 6 wrinkle net");
}

void BM_EnginePlusBarnet(benchmark::State& state) {
  lb::ArmSession s(sinew::rigc::SkinChoice::kLinear);
  int64_t i = 0;
  for (auto _ : state) {
    set_elbow(s, i++);
    benchmark::DoNotOptimize(s.step());
  }
  report(state, s.rig().vertex_count());
  state.SetLabel("arm LBS + elbow bar-net");
}

BENCHMARK(BM_EngineStep)->Arg(0)->Arg(1)->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_BarnetStep)->Arg(8)->Arg(16)->Arg(32)->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_BarnetStepRefactor)->Arg(8)->Arg(16)->Arg(32)->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_BarnetStepSpecOrder)->ArgsProduct({{8, 16, 32}, {0, 1}})->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_BarnetFigureNet)->Arg(3)->Arg(6)->UseRealTime()->Unit(benchmark::kMicrosecond);
BENCHMARK(BM_EnginePlusBarnet)->UseRealTime()->Unit(benchmark::kMicrosecond);

// The per-layer table, every figure measured here, in this run.
bool summary() {
  bool ok = true;
  lb::ArmSession lbs(sinew::rigc::SkinChoice::kLinear), dqs(sinew::rigc::SkinChoice::kDualQuaternion);
  const double t_lbs = lbs_baseline();
  const double t_dqs = median_seconds(
      [&](int i) {
        set_elbow(dqs, i);
        benchmark::DoNotOptimize(dqs.engine_step());
      },
      200);
  std::printf("\nbarnet bench: per step on the built-in arm (%u skin vertices), medians of this run\n",
              lbs.rig().vertex_count());
  std::printf("  %-44s %10.2f us  x%.3f\n", "engine step, LBS (baseline)", t_lbs * 1e6, 1.0);
  std::printf("  %-44s %10.2f us  x%.3f\n", "engine step, DQS", t_dqs * 1e6, t_dqs / t_lbs);
  for (int segments : {8, 16, 32}) {
    BarnetStepLoop plain(net_options(segments));
    lb::ArmSession& s = plain.session();
    const double t = median_seconds([&](int i) { benchmark::DoNotOptimize(plain.step(i)); }, 500);
    char what[96];
    std::snprintf(what, sizeof(what), "bar-net step, %zu nodes / %u free / %zu wrapped", s.model().nodes.size(),
                  s.state().free_count, s.model().wrap.size());
    std::printf("  %-44s %10.2f us  x%.3f  (%.1f ns per wrapped vertex)\n", what, t * 1e6, t / t_lbs,
                t * 1e9 / static_cast<double>(s.model().wrap.size()));
    sinew::bench::SummaryRow row;
    row.bench = "barnet";
    row.measure = what;
    row.figure = t * 1e6;
    row.unit = "us";
    row.baseline = "LBS engine step";
    row.baseline_figure = t_lbs * 1e6;
    if (segments == 32) {  // the target is set at 224 nodes
      row.target = sinew::bench::ratio_at_most(0.3);
      row.target_source = "performance issue: bar-net wrap <= 0.3x LBS at 224 nodes";
    }
    if (!sinew::bench::summary_row(row)) ok = false;

    // The same net with q from an input: the step plus a re-factorisation.
    BarnetStepLoop refactor(net_options(segments, true));
    lb::ArmSession& r = refactor.session();
    const double t_refactor = median_seconds([&](int i) { benchmark::DoNotOptimize(refactor.step(i)); }, 500);
    std::snprintf(what, sizeof(what), "  + q from an input (refactor, %llu products)",
                  static_cast<unsigned long long>(r.state().refactor_products));
    std::printf("  %-44s %10.2f us  x%.3f  (x%.3f the plain bar-net step)\n", what, t_refactor * 1e6,
                t_refactor / t_lbs, t_refactor / t);

    // The same two with the free nodes in the spec's order.
    BarnetStepLoop spec_order(net_options(segments, false, false)), spec_order_q(net_options(segments, true, false));
    const double t_spec = median_seconds([&](int i) { benchmark::DoNotOptimize(spec_order.step(i)); }, 500);
    const double t_spec_q = median_seconds([&](int i) { benchmark::DoNotOptimize(spec_order_q.step(i)); }, 500);
    std::snprintf(what, sizeof(what), "  spec order (profile %u, RCM %u)", spec_order.session().state().profile,
                  s.state().profile);
    std::printf("  %-44s %10.2f us  x%.3f  (x%.3f the plain bar-net step)\n", what, t_spec * 1e6, t_spec / t_lbs,
                t_spec / t);
    std::snprintf(what, sizeof(what), "  spec order + q from an input (%llu products)",
                  static_cast<unsigned long long>(spec_order_q.session().state().refactor_products));
    std::printf("  %-44s %10.2f us  x%.3f  (x%.3f the refactoring step)\n", what, t_spec_q * 1e6, t_spec_q / t_lbs,
                t_spec_q / t_refactor);
  }
  return ok;
}

}  // namespace

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return summary() ? 0 : 1;
}
