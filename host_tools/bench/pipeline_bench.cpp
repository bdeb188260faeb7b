// sinew-bench-pipeline: the built-in arm's whole tick, with the default
// job's layers and with every layer on, beside skinning alone in the same
// run: step p50/p99/max, each stage's mean and share of the step; each on
// one thread and on N workers (firmware/runtime/worker_pool.hpp), with the
// scaling between the two.
//   sinew-bench-pipeline [--rig arm|hand] [--steps N] [--workers N]
#include <CLI/CLI.hpp>
#include <algorithm>
#include <cstdio>
#include <memory>
#include <thread>

#include "firmware/runtime/worker_pool.hpp"
#include "host_tools/bench/common/bench_summary.hpp"
#include "host_tools/run/pipeline_run.hpp"

namespace {

namespace sb = sinew::bench;
namespace pl = sinew::pipeline;

struct Config {
  const char* name;
  const char* layers;
  double one_thread_p99_us = 0;  // target on one thread (0: none)
  const char* one_thread_source = "";
  double workers_p99_us = 0;  // target on 2 workers (0: none)
  const char* workers_source = "";
};

bool bench_config(const std::string& rig_name, const Config& c, int steps, const sinew::layer::Workers* workers,
                  uint32_t threads, sinew::run::RunFigures* out) {
  pl::PipelineOptions options;
  options.workers = workers;
  std::string error;
  const auto run = std::make_unique<sinew::run::PipelineRun>();
  if (!sinew::run::parse_layer_list(c.layers, &options, &error) ||
      !sinew::run::pipeline_run_init(rig_name, options, run.get(), &error)) {
    std::fprintf(stderr, "sinew-bench-pipeline: %s: %s\n", c.name, error.c_str());
    return false;
  }
  sinew::run::pipeline_run_steps(run.get(), steps / 10 + 1);  // warm caches and the layers' state
  *out = sinew::run::pipeline_run_steps(run.get(), steps, static_cast<uint32_t>(steps / 10 + 1));
  const double p50 = out->percentile(0.5);
  const std::string name =
      std::string(c.name) + (workers == nullptr ? ", 1 thread" : ", " + std::to_string(threads) + " workers");
  std::printf("%-44s p50 %8.1f us  p99 %8.1f us  max %8.1f us  layer errors %llu\n", name.c_str(), p50,
              out->percentile(0.99), out->step_us.back(), static_cast<unsigned long long>(out->layer_errors));
  double total = 0;
  for (double m : out->stage_mean_us) total += m;
  std::printf("%-44s", "");
  for (uint32_t k = 0; k < pl::kStageCount; ++k)
    if (pl::pipeline_stage_on(run->pipeline, static_cast<pl::Stage>(k)))
      std::printf(" %s %.1f us (%.0f%%);", pl::stage_name(static_cast<pl::Stage>(k)), out->stage_mean_us[k],
                  total > 0 ? 100.0 * out->stage_mean_us[k] / total : 0.0);
  std::printf("\n");
  return out->layer_errors == 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"sinew-bench-pipeline: the built-in rig's tick per layer set, against skinning alone"};
  std::string rig_name = "arm";
  int steps = 2000;
  int workers = 0;
  app.add_option("--rig", rig_name, "built-in rig")->check(CLI::IsMember({"arm", "hand"}));
  app.add_option("--steps", steps, "timed steps per configuration")->check(CLI::Range(10, 10000000));
  app.add_option("--workers", workers, "worker threads for the parallel stages (0: every CPU, at most 4)")
      ->check(CLI::Range(0, static_cast<int>(sinew::layer::kMaxParts)));
  CLI11_PARSE(app, argc, argv);
  // The bench has no I/O threads: by default every CPU (at most 4) works.
  const uint32_t threads =
      static_cast<uint32_t>(workers > 0 ? workers : std::min(4u, std::max(1u, std::thread::hardware_concurrency())));
  sinew::firmware::WorkerPool pool;
  std::string report, error;
  if (!pool.start(threads, 0, -1, &report, &error)) {
    std::fprintf(stderr, "sinew-bench-pipeline: %s\n", error.c_str());
    return 1;
  }

  const Config baseline{"skinning only", "none"};
  const Config configs[] = {{"default job (metaballs, barnet)", "metaballs,barnet", 400,
                             "performance issue: default job p99 <= 400 us, 1 worker"},
                            {"every layer", "all", 2000, "performance issue: every layer p99 <= 2 ms, 1 worker", 1000,
                             "performance issue: every layer p99 <= 1 ms, 2 workers"}};
  std::printf("sinew-bench-pipeline: rig %s, %d steps per configuration, 1 thread and %u workers\n", rig_name.c_str(),
              steps, threads);
  sinew::run::RunFigures base;
  if (!bench_config(rig_name, baseline, steps, nullptr, 1, &base)) return 1;
  bool ok = true;
  for (const Config& c : configs) {
    sinew::run::RunFigures one, many;
    if (!bench_config(rig_name, c, steps, nullptr, 1, &one) ||
        (threads > 1 && !bench_config(rig_name, c, steps, pool.workers(), threads, &many))) {
      ok = false;
      continue;
    }
    // Performance issue's tick budget: the default job p99 <= 400 us on one
    // thread; every layer p99 <= 2 ms on one thread, <= 1 ms on 2 workers.
    sb::SummaryRow row;
    row.bench = "pipeline";
    row.measure = rig_name + ", " + c.name + ", 1 thread, step p99";
    row.figure = one.percentile(0.99);
    row.unit = "us";
    row.baseline = "skinning only, step p99";
    row.baseline_figure = base.percentile(0.99);
    row.target = sb::figure_at_most(c.one_thread_p99_us);
    row.target_source = c.one_thread_source;
    ok = sb::summary_row(row) && ok;
    if (threads > 1) {
      sb::SummaryRow scaling;
      scaling.bench = "pipeline";
      scaling.measure = rig_name + ", " + c.name + ", " + std::to_string(threads) + " workers, step p99";
      scaling.figure = many.percentile(0.99);
      scaling.unit = "us";
      scaling.baseline = "the same on 1 thread, step p99";
      scaling.baseline_figure = one.percentile(0.99);
      if (c.workers_p99_us > 0 && threads == 2) {  // the target is stated for this machine's 2 workers
        scaling.target = sb::figure_at_most(c.workers_p99_us);
        scaling.target_source = c.workers_source;
      }
      ok = sb::summary_row(scaling) && ok;
    }
  }
  return ok ? 0 : 1;
}
