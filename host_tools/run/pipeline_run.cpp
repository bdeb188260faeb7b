#include "host_tools/run/pipeline_run.hpp"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <sstream>

#include "hal/sim/sweep.hpp"
#include "host_tools/determinism/output_hash.hpp"
#include "host_tools/layers/builtin_layers.hpp"

namespace sinew::run {

bool parse_layer_list(const std::string& text, pipeline::PipelineOptions* o, std::string* error) {
  o->sph = o->metaballs = o->barnet = o->anatomy = text == "all";
  if (text == "all" || text == "none") return true;
  std::stringstream list(text);
  for (std::string name; std::getline(list, name, ',');) {
    if (name == "sph")
      o->sph = true;
    else if (name == "metaballs")
      o->metaballs = true;
    else if (name == "barnet")
      o->barnet = true;
    else if (name == "anatomy")
      o->anatomy = true;
    else
      return *error = "--layers: unknown layer '" + name + "' (sph, metaballs, barnet, anatomy)", false;
  }
  return true;
}

bool pipeline_run_init(const std::string& rig_name, const pipeline::PipelineOptions& options, PipelineRun* run,
                       std::string* error) {
  std::vector<uint8_t> bytes;
  if (!layers::compile_builtin(rig_name, &bytes, &run->layer_report, error)) return false;
  run->blob_bytes = bytes.size();
  run->blob.assign(bytes.size() / 8 + 1, 0);
  std::memcpy(run->blob.data(), bytes.data(), bytes.size());
  const auto* data = reinterpret_cast<const uint8_t*>(run->blob.data());
  size_t rig_bytes = 0, layer_bytes = 0;
  rig::LoadStatus st = rig::rig_validate(data, bytes.size(), &rig_bytes);
  run->rig_arena.assign(rig_bytes / 8 + 1, 0);
  if (st.ok()) st = rig::rig_init(data, bytes.size(), run->rig_arena.data(), run->rig_arena.size() * 8, &run->rig);
  if (st.ok()) st = pipeline::layers_validate(run->rig, data, bytes.size(), &layer_bytes);
  run->layer_arena.assign(layer_bytes / 8 + 1, 0);
  if (st.ok())
    st = pipeline::layers_init(run->rig, data, bytes.size(), run->layer_arena.data(), run->layer_arena.size() * 8,
                               &run->layers);
  if (!st.ok()) return *error = st.message, false;
  run->state.assign(pipeline::pipeline_state_bytes(run->rig, run->layers, options) / 8 + 1, 0);
  const pipeline::PipelineStatus ps =
      pipeline::pipeline_init(run->rig, run->layers, options, run->state.data(), run->state.size() * 8, &run->pipeline);
  if (!ps.ok()) return *error = ps.message, false;
  run->inputs.assign(run->pipeline.input_count, 0);
  return true;
}

double RunFigures::percentile(double q) const {
  if (step_us.empty()) return 0;
  return step_us[static_cast<size_t>(q * (static_cast<double>(step_us.size()) - 1))];
}

RunFigures pipeline_run_steps(PipelineRun* run, int steps, uint32_t first) {
  using clock = std::chrono::steady_clock;
  pipeline::Pipeline& p = run->pipeline;
  RunFigures f;
  f.step_us.resize(static_cast<size_t>(steps));
  determinism::OutputHash hash;
  for (int s = 0; s < steps; ++s) {
    const uint32_t tick = first + static_cast<uint32_t>(s);
    for (uint32_t i = 0; i < run->rig.input_count; ++i) run->inputs[i] = hal::sim::sweep_input(i, tick);
    const auto t0 = clock::now();
    for (uint32_t k = 0; k < pipeline::kStageCount; ++k) {
      const auto stage = static_cast<pipeline::Stage>(k);
      if (!pipeline::pipeline_stage_on(p, stage)) continue;
      const auto a = clock::now();
      f.layer_errors += pipeline::pipeline_run_stage(&p, stage, run->inputs).ok() ? 0u : 1u;
      f.stage_mean_us[k] += std::chrono::duration<double, std::micro>(clock::now() - a).count();
    }
    f.step_us[static_cast<size_t>(s)] = std::chrono::duration<double, std::micro>(clock::now() - t0).count();
    f.clamped_dofs += p.engine.stats.clamped_dofs;
    for (int c = 0; c < 3; ++c)
      for (uint32_t v = 0; v < run->rig.vertex_count(); ++v) hash.add_i32(p.engine.vertices.position[c][v]);
  }
  for (double& mean : f.stage_mean_us) mean /= static_cast<double>(steps);
  std::sort(f.step_us.begin(), f.step_us.end());
  f.output_hash = hash.digest();
  return f;
}

}  // namespace sinew::run
