// The metaballs stage (metaballs-pbd-skinning; docs/metaballs.md): adds
// (metaballs skin - R) over every vertex.
#include "sim_core/metaballs/step.hpp"
#include "sim_core/metaballs/validate.hpp"
#include "stage_fns.hpp"

namespace sinew::pipeline::stages {

uint32_t metaballs_compiled(const LayerSet& layers) { return layers.metaballs.present ? 1u : 0u; }

// The metaballs skin is computed over every vertex, then added.
SharedNeeds metaballs_shares(const rig::Rig& rig, const LayerSet&) {
  return {.reference = true, .scratch_vertices = rig.vertex_count()};
}

void metaballs_describe(const rig::Rig&, const LayerSet& layers, rig::MessageBuilder* out) {
  if (layers.metaballs.present) out->text("metaballs");
}

PipelineStatus metaballs_validate(const rig::Rig& rig, const LayerSet& layers) {
  if (!layers.metaballs.present) return {};
  const layer::LayerStatus st = metaballs::metaballs_validate(layers.metaballs.model, rig);
  if (!st.ok()) return stage_fail(PipelineError::kBadModel, "metaballs", st.message);
  return {};
}

size_t metaballs_state_bytes(const rig::Rig&, const LayerSet& layers, const PipelineOptions&) {
  return layers.metaballs.present ? metaballs::metaballs_state_bytes(layers.metaballs.model) : 0;
}

PipelineStatus metaballs_init(Pipeline* p, uint8_t* block, size_t bytes) {
  layer::LayerStatus st = metaballs::metaballs_init(p->layers->metaballs.model, block, bytes, &p->metaballs.state);
  // Physical jiggle gains are converted from the section's rate to the
  // loop's (as SPH's gains are).
  if (st.ok() && p->options.tick_hz != 0) st = metaballs::set_tick_rate(&p->metaballs.state, p->options.tick_hz);
  if (!st.ok()) return stage_fail(PipelineError::kBadModel, "metaballs", st.message);
  p->metaballs.on = true;
  return {};
}

PipelineStatus metaballs_step(Pipeline* p, std::span<const int32_t>) {
  skin::SkinnedVertices out;
  for (int a = 0; a < 3; ++a) out.position[a] = p->scratch[a].first(p->rig->vertex_count());
  const layer::LayerStatus st =
      metaballs::metaballs_step(&p->metaballs.state, p->engine.model, out, p->options.workers);
  if (!st.ok()) return stage_fail(PipelineError::kLayer, "metaballs", st.message);
  for (int a = 0; a < 3; ++a) add_displacements(p, a, p->scratch[a].first(p->rig->vertex_count()));
  return {};
}

// No input flag of its own.
void metaballs_flag_inputs(const Pipeline&, std::span<uint8_t>) {}

}  // namespace sinew::pipeline::stages
