// The main job's computation on a built-in rig, as fast as it can run: the
// built-in blob with its layers (the one the daemon embeds) stepped through
// sim_core's pipeline over the built-in joint sweep, timing each stage.
// Shared by sinew-run and sinew-bench-pipeline.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "sim_core/pipeline/pipeline.hpp"

namespace sinew::run {

// "all", "none", or a comma list of sph, metaballs, barnet, anatomy.
bool parse_layer_list(const std::string& text, pipeline::PipelineOptions* options, std::string* error);

// A compiled built-in rig and its pipeline. Memory is sized once here; the
// steps never allocate. Not movable: the pipeline points into its own state.
struct PipelineRun {
  PipelineRun() = default;
  PipelineRun(const PipelineRun&) = delete;
  PipelineRun& operator=(const PipelineRun&) = delete;

  std::vector<std::string> layer_report;  // rigc's line per compiled layer
  size_t blob_bytes = 0;
  std::vector<uint64_t> blob, rig_arena, layer_arena, state;
  rig::Rig rig;
  pipeline::LayerSet layers;
  pipeline::Pipeline pipeline;
  std::vector<int32_t> inputs;  // rig inputs, then external inputs (held at 0)
};

// Compiles the built-in rig ("arm" or "hand") and initialises its pipeline
// with the given layers switched on.
bool pipeline_run_init(const std::string& rig_name, const pipeline::PipelineOptions& options, PipelineRun* run,
                       std::string* error);

struct RunFigures {
  std::vector<double> step_us;                       // every step's time, sorted ascending
  double stage_mean_us[pipeline::kStageCount] = {};  // stages that are off stay 0
  uint64_t clamped_dofs = 0, layer_errors = 0;
  uint64_t output_hash = 0;  // xxh64 of every step's positions (the determinism line)

  double percentile(double q) const;  // q in [0, 1]
};

// Runs `steps` ticks of the sweep from tick `first`, timing each stage.
RunFigures pipeline_run_steps(PipelineRun* run, int steps, uint32_t first = 0);

}  // namespace sinew::run
