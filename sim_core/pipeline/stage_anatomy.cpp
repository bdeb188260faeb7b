// The anatomy stage (anatomically-based-modeling, leman-elastic-skin;
// docs/anatomy.md): the muscles, then the elastic skin; adds (relaxed skin -
// R) over the skin's support region.
#include <algorithm>

#include "sim_core/elastic_skin/skin_step.hpp"
#include "sim_core/elastic_skin/skin_validate.hpp"
#include "sim_core/fixed/arena.hpp"
#include "sim_core/muscle/muscle_step.hpp"
#include "sim_core/muscle/muscle_validate.hpp"
#include "stage_fns.hpp"

namespace sinew::pipeline {

uint32_t* anatomy_skin_iterations_option(PipelineOptions* o) { return &o->anatomy.skin_iterations; }
uint32_t* anatomy_skin_max_anchor_acceleration_option(PipelineOptions* o) {
  return &o->anatomy.skin_max_anchor_acceleration;
}
bool* anatomy_skin_whole_mesh_option(PipelineOptions* o) { return &o->anatomy.skin_whole_mesh; }

namespace stages {
namespace {

// An acceleration input (Q16.16 m/s^2) in the skin's Q24.8 rig units / s^2:
// one rig unit is 2^length_exponent m, so the value shifts right by
// 8 + length_exponent (rounded half up, or left and saturated).
int32_t rig_acceleration(int32_t q16_metres, int32_t length_exponent) {
  const int shift = 16 - elastic_skin::kAccelFracBits + length_exponent;  // -8..24
  if (shift > 0) return fx::sat_i32(fx::round_shift(q16_metres, shift));
  return fx::sat_i32(int64_t{q16_metres} * (int64_t{1} << -shift));
}

}  // namespace

uint32_t anatomy_compiled(const LayerSet& layers) { return layers.anatomy.has_muscles ? 1u : 0u; }

// Muscles alone displace nothing; the elastic skin adds (relaxed skin - R).
SharedNeeds anatomy_shares(const rig::Rig&, const LayerSet& layers) { return {.reference = layers.anatomy.has_skin}; }

void anatomy_describe(const rig::Rig&, const LayerSet& layers, rig::MessageBuilder* out) {
  if (layers.anatomy.has_muscles) out->text(layers.anatomy.has_skin ? "anatomy(muscles, skin)" : "anatomy(muscles)");
}

PipelineStatus anatomy_validate(const rig::Rig& rig, const LayerSet& layers) {
  if (!layers.anatomy.has_muscles) return {};
  layer::LayerStatus st = muscle::muscle_validate(layers.anatomy.muscles, rig);
  if (st.ok() && layers.anatomy.has_skin)
    st = elastic_skin::skin_validate(layers.anatomy.skin, rig, layers.anatomy.muscles);
  if (!st.ok()) return stage_fail(PipelineError::kBadModel, "anatomy", st.message);
  return {};
}

size_t anatomy_state_bytes(const rig::Rig&, const LayerSet& layers, const PipelineOptions&) {
  if (!layers.anatomy.has_muscles) return 0;
  fx::ArenaCarver c(nullptr, 0);
  c.raw(muscle::muscle_state_bytes(layers.anatomy.muscles));
  if (layers.anatomy.has_skin) c.raw(elastic_skin::skin_state_bytes(layers.anatomy.skin));
  return c.needed();
}

PipelineStatus anatomy_init(Pipeline* p, uint8_t* block, size_t bytes) {
  const LayerSet& layers = *p->layers;
  fx::ArenaCarver c(block, bytes);
  const size_t muscle_bytes = muscle::muscle_state_bytes(layers.anatomy.muscles);
  layer::LayerStatus st =
      muscle::muscle_init(layers.anatomy.muscles, c.raw(muscle_bytes), muscle_bytes, &p->anatomy.muscles);
  if (st.ok() && layers.anatomy.has_skin) {
    // The moving vertices are chosen at init: the region and its halo, or
    // every vertex with skin_whole_mesh (the same state size either way).
    elastic_skin::SkinModel skin = layers.anatomy.skin;
    if (p->options.anatomy.skin_whole_mesh) skin.region = {};
    const size_t skin_bytes = elastic_skin::skin_state_bytes(skin);
    st = elastic_skin::skin_init(skin, c.raw(skin_bytes), skin_bytes, &p->anatomy.skin);
  }
  if (!st.ok()) return stage_fail(PipelineError::kBadModel, "anatomy", st.message);
  p->anatomy.on = true;
  return {};
}

PipelineStatus anatomy_step(Pipeline* p, std::span<const int32_t> inputs) {
  const layer::LayerStatus ms = muscle::muscle_step(p->layers->anatomy.muscles, p->engine.model, &p->anatomy.muscles);
  if (!ms.ok()) return stage_fail(PipelineError::kLayer, "muscles", ms.message);
  if (!p->layers->anatomy.has_skin) return {};
  elastic_skin::SkinModel model = p->layers->anatomy.skin;
  if (p->options.anatomy.skin_iterations != 0) model.params.iterations = p->options.anatomy.skin_iterations;
  // The dynamic skin's time step: the loop's rate, else the rate the rig
  // was built for, else rigc's default rate (1 kHz).
  elastic_skin::SkinTick tick;
  tick.workers = p->options.workers;  // the static step's per-vertex and per-edge loops
  tick.tick_hz = p->options.tick_hz != 0 ? p->options.tick_hz : (p->layers->rate_hz != 0 ? p->layers->rate_hz : 1000);
  // The base's measured acceleration (LEMAN §3: the skin feels -a_base).
  int32_t base[3] = {0, 0, 0};
  for (int c = 0; c < 3; ++c) {
    const uint32_t k = p->layers->anatomy.skin_base_acceleration[c];
    if (k != kNoExternalInput) base[c] = rig_acceleration(inputs[p->rig->input_count + k], p->rig->length_exponent);
  }
  tick.base_acceleration = {base[0], base[1], base[2]};
  const uint32_t cap = std::min<uint32_t>(p->options.anatomy.skin_max_anchor_acceleration, 32767);
  tick.max_anchor_acceleration = rig_acceleration(static_cast<int32_t>(cap << 16), p->rig->length_exponent);
  const layer::LayerStatus ss = elastic_skin::skin_step(model, p->layers->anatomy.muscles, p->anatomy.muscles,
                                                        p->engine.model, tick, &p->anatomy.skin);
  if (!ss.ok()) return stage_fail(PipelineError::kLayer, "elastic skin", ss.message);
  const std::span<const uint32_t> region = p->layers->anatomy.skin_region;
  if (region.empty()) {
    for (int a = 0; a < 3; ++a) add_displacements(p, a, p->anatomy.skin.position[a].first(model.vertex_count));
    return {};
  }
  // The support region: weight x (relaxed - reference), Q2.30 weights.
  for (size_t i = 0; i < region.size(); ++i) {
    const uint32_t v = region[i];
    const fx::Unit w = p->layers->anatomy.skin_region_weight[i];
    for (int a = 0; a < 3; ++a) {
      const int64_t delta = int64_t{p->anatomy.skin.position[a][v]} - p->reference[a][v];
      add_displacement(p, a, v, fx::sat_i32(p->reference[a][v] + fx::round_shift(delta * w, fx::kUnitFracBits)));
    }
  }
  return {};
}

// No input flag of its own.
void anatomy_flag_inputs(const Pipeline&, std::span<uint8_t>) {}

}  // namespace stages
}  // namespace sinew::pipeline
