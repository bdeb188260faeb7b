#include "host_tools/run/pipeline_run.hpp"

#include <algorithm>
#include <chrono>
#include <cstring>
#include <sstream>

#include "hal/sim/sweep.hpp"
#include "host_tools/determinism/output_hash.hpp"
#include "host_tools/layers/builtin_layers.hpp"
#include "sim_core/pipeline/stage_table.hpp"

namespace sinew::run {

bool parse_layer_list(const std::string& text, pipeline::PipelineOptions* o, std::string* error) {
  o->stages = text == "all" ? pipeline::StageSet::all() : pipeline::StageSet::none();
  if (text == "all" || text == "none") return true;
  std::stringstream list(text);
  for (std::string name; std::getline(list, name, ',');) {
    const pipeline::StageInfo* stage = pipeline::find_stage(name.data(), name.size());
    if (stage == nullptr || stage->stage == pipeline::Stage::kSkinning) {
      std::string known;
      for (const pipeline::StageInfo& s : pipeline::kStages)
        if (s.stage != pipeline::Stage::kSkinning) known += (known.empty() ? "" : ", ") + std::string(s.name);
      return *error = "--layers: unknown layer '" + name + "' (" + known + ")", false;
    }
    o->stages.set(stage->stage, true);
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

namespace {

uint64_t steady_now(void*) {
  return static_cast<uint64_t>(
      std::chrono::duration_cast<std::chrono::nanoseconds>(std::chrono::steady_clock::now().time_since_epoch())
          .count());
}

}  // namespace

RunFigures pipeline_run_steps(PipelineRun* run, int steps, uint32_t first) {
  pipeline::Pipeline& p = run->pipeline;
  RunFigures f;
  f.step_us.resize(static_cast<size_t>(steps));
  determinism::OutputHash hash;
  const pipeline::StepProbe probe{steady_now, nullptr, nullptr};
  for (int s = 0; s < steps; ++s) {
    const uint32_t tick = first + static_cast<uint32_t>(s);
    for (uint32_t i = 0; i < run->rig.input_count; ++i) run->inputs[i] = hal::sim::sweep_input(i, tick);
    pipeline::StepReport report;
    const uint64_t t0 = steady_now(nullptr);
    f.layer_errors += pipeline::pipeline_step(&p, run->inputs, &probe, &report).ok() ? 0u : 1u;
    f.step_us[static_cast<size_t>(s)] = static_cast<double>(steady_now(nullptr) - t0) / 1000.0;
    for (uint32_t k = 0; k < pipeline::kStageCount; ++k)
      f.stage_mean_us[k] += static_cast<double>(report.stage_ns[k]) / 1000.0;
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
