// sinew-run: the main job's computation on a built-in rig, as fast as it
// can: the built-in blob with its layers (the one the daemon embeds), run
// through sim_core's pipeline over the built-in joint sweep. Prints the rig
// summary, the step time per pipeline stage and the determinism hash of the
// outputs.
//   sinew-run [--rig arm|hand] [--steps N] [--layers all|none|sph,metaballs,barnet,anatomy]
#include <CLI/CLI.hpp>
#include <cstdio>
#include <memory>

#include "host_tools/determinism/output_hash.hpp"
#include "host_tools/run/pipeline_run.hpp"

int main(int argc, char** argv) {
  CLI::App app{"sinew-run: run the pipeline on a built-in rig"};
  std::string rig_name = "arm", layers = "none";
  int steps = 5000;
  app.add_option("--rig", rig_name, "built-in rig")->check(CLI::IsMember({"arm", "hand"}));
  app.add_option("--steps", steps, "pipeline steps")->check(CLI::Range(1, 10000000));
  app.add_option("--layers", layers, "all, none, or a comma list of sph, metaballs, barnet, anatomy");
  CLI11_PARSE(app, argc, argv);

  using namespace sinew;
  pipeline::PipelineOptions options;
  std::string error;
  const auto run = std::make_unique<run::PipelineRun>();
  if (!run::parse_layer_list(layers, &options, &error) ||
      !run::pipeline_run_init(rig_name, options, run.get(), &error)) {
    std::fprintf(stderr, "sinew-run: %s\n", error.c_str());
    return 1;
  }
  std::printf("rig %s: blob %zu B\n", rig_name.c_str(), run->blob_bytes);
  for (const std::string& line : run->layer_report) std::printf("  layer %s\n", line.c_str());

  const run::RunFigures f = run::pipeline_run_steps(run.get(), steps);
  std::printf("steps %d: step time p50 %.1f us, p99 %.1f us, max %.1f us (%.1f%% of a 1 kHz tick at p99)\n", steps,
              f.percentile(0.5), f.percentile(0.99), f.step_us.back(), f.percentile(0.99) / 10.0);
  std::printf("mean per stage:");
  for (uint32_t k = 0; k < pipeline::kStageCount; ++k)
    if (pipeline::pipeline_stage_on(run->pipeline, static_cast<pipeline::Stage>(k)))
      std::printf(" %s %.1f us;", pipeline::stage_name(static_cast<pipeline::Stage>(k)), f.stage_mean_us[k]);
  std::printf("\nclamped DOF events %llu, saturated values in the last step %u, layer errors %llu\n",
              static_cast<unsigned long long>(f.clamped_dofs), run->pipeline.engine.stats.saturated,
              static_cast<unsigned long long>(f.layer_errors));
  determinism::print_determinism_line(("run-" + rig_name).c_str(), f.output_hash);
  return f.layer_errors == 0 ? 0 : 1;
}
