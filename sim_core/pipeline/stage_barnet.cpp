// The bar-net stage (barnet-driven-skinning; docs/barnet.md): each net adds
// (wrapped skin - R) over its wrap vertices.
#include <algorithm>

#include "sim_core/barnet/barnet_step.hpp"
#include "sim_core/barnet/barnet_validate.hpp"
#include "sim_core/fixed/arena.hpp"
#include "stage_fns.hpp"

namespace sinew::pipeline::stages {

uint32_t barnet_compiled(const LayerSet& layers) { return layers.barnet.count; }

// Each net's node positions, then its wrapped vertices, before they are added.
SharedNeeds barnet_shares(const rig::Rig&, const LayerSet& layers) {
  SharedNeeds n{.reference = true};
  for (uint32_t i = 0; i < layers.barnet.count; ++i) {
    n.scratch_vertices = std::max(n.scratch_vertices, static_cast<uint32_t>(layers.barnet.net[i].wrap.size()));
    n.node_outputs = std::max(n.node_outputs, static_cast<uint32_t>(layers.barnet.net[i].nodes.size()));
  }
  return n;
}

void barnet_describe(const rig::Rig&, const LayerSet& layers, rig::MessageBuilder* out) {
  for (uint32_t i = 0; i < layers.barnet.count; ++i) out->text(i > 0 ? " barnet" : "barnet");
}

PipelineStatus barnet_validate(const rig::Rig& rig, const LayerSet& layers) {
  for (uint32_t i = 0; i < layers.barnet.count; ++i) {
    const layer::LayerStatus st = barnet::barnet_validate(layers.barnet.net[i], rig);
    if (!st.ok()) return stage_fail(PipelineError::kBadModel, "barnet", st.message, i);
    // The net's loads read external inputs below its external_count.
    if (layers.barnet.net[i].external_count > layers.external_count())
      return stage_fail(PipelineError::kBadModel, "barnet", "external_count: exceeds the layer set's external inputs",
                        i);
  }
  return {};
}

size_t barnet_state_bytes(const rig::Rig&, const LayerSet& layers, const PipelineOptions&) {
  fx::ArenaCarver c(nullptr, 0);
  for (uint32_t i = 0; i < layers.barnet.count; ++i) c.raw(barnet::barnet_state_bytes(layers.barnet.net[i]));
  return c.needed();
}

PipelineStatus barnet_init(Pipeline* p, uint8_t* block, size_t bytes) {
  fx::ArenaCarver c(block, bytes);
  p->barnet.count = p->layers->barnet.count;
  for (uint32_t i = 0; i < p->barnet.count; ++i) {
    const barnet::BarnetModel& m = p->layers->barnet.net[i];
    const size_t need = barnet::barnet_state_bytes(m);
    const layer::LayerStatus st = barnet::barnet_init(m, c.raw(need), need, &p->barnet.net[i]);
    if (!st.ok()) return stage_fail(PipelineError::kBadModel, "barnet", st.message, i);
  }
  return {};
}

PipelineStatus barnet_step(Pipeline* p, std::span<const int32_t> inputs) {
  PipelineStatus first;
  for (uint32_t i = 0; i < p->barnet.count; ++i) {
    const barnet::BarnetModel& m = p->layers->barnet.net[i];
    barnet::StepOutputs out;
    for (int a = 0; a < 3; ++a) {
      out.node[a] = p->node_outputs[a];
      out.skin[a] = p->scratch[a];
    }
    const layer::LayerStatus st = barnet::barnet_step(
        &p->barnet.net[i], {p->engine.model, inputs.first(p->rig->input_count), inputs.subspan(p->rig->input_count)},
        out);
    if (!st.ok()) {
      if (first.ok()) first = stage_fail(PipelineError::kLayer, "barnet", st.message, i);
      continue;
    }
    for (size_t k = 0; k < m.wrap.size(); ++k)
      for (int a = 0; a < 3; ++a) add_displacement(p, a, m.wrap[k].vertex, p->scratch[a][k]);
  }
  return first;
}

// No input flag of its own.
void barnet_flag_inputs(const Pipeline&, std::span<uint8_t>) {}

}  // namespace sinew::pipeline::stages
