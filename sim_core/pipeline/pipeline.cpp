#include "pipeline.hpp"

#include <algorithm>

#include "sim_core/barnet/barnet_step.hpp"
#include "sim_core/elastic_skin/skin_step.hpp"
#include "sim_core/fixed/arena.hpp"
#include "sim_core/fixed/quat.hpp"
#include "sim_core/fixed/trig.hpp"
#include "sim_core/metaballs/step.hpp"
#include "sim_core/muscle/muscle_step.hpp"
#include "sim_core/rig/message.hpp"
#include "sim_core/sph/sph_step.hpp"
#include "stage_table.hpp"

namespace sinew::pipeline {
namespace {

PipelineStatus fail(PipelineError e, const char* what, const char* detail = nullptr, int64_t index = -1) {
  PipelineStatus s;
  s.error = e;
  rig::MessageBuilder m(s.message, sizeof(s.message));
  m.text(what);
  if (index >= 0) m.text("[").number(index).text("]");
  if (detail != nullptr) m.text(": ").text(detail);
  return s;
}

uint32_t largest_barnet_nodes(const LayerSet& layers) {
  uint32_t n = 0;
  for (uint32_t i = 0; i < layers.barnet_count; ++i)
    n = std::max(n, static_cast<uint32_t>(layers.barnet[i].nodes.size()));
  return n;
}

uint32_t largest_barnet_wrap(const LayerSet& layers) {
  uint32_t n = 0;
  for (uint32_t i = 0; i < layers.barnet_count; ++i)
    n = std::max(n, static_cast<uint32_t>(layers.barnet[i].wrap.size()));
  return n;
}

// One layout for counting and carving. Sub-arenas of the layers are raw
// blocks; each layer carves its own state inside with the same carver.
struct Blocks {
  uint8_t* engine = nullptr;
  uint8_t* sph[kMaxSphJoints] = {};
  uint8_t* metaballs = nullptr;
  uint8_t* muscles = nullptr;
  uint8_t* skin = nullptr;
  uint8_t* barnet[kMaxBarnets] = {};
};

fx::ArenaCarver layout(const rig::Rig& rig, const LayerSet& layers, const PipelineOptions& o, void* base, size_t size,
                       Pipeline* p, Blocks* b) {
  fx::ArenaCarver c(base, size);
  const size_t n = rig.vertex_count();
  b->engine = c.raw(engine::engine_arena_bytes(rig));
  const uint32_t sph_count = o.stages.has(Stage::kSph) ? layers.sph_count : 0;
  // The state size does not depend on the gains (nor on the rate).
  for (uint32_t i = 0; i < sph_count; ++i) b->sph[i] = c.raw(sph::sph_state_bytes(layers.sph[i].model));
  if (o.stages.has(Stage::kMetaballs) && layers.has_metaballs)
    b->metaballs = c.raw(metaballs::state_bytes(layers.metaballs));
  if (o.stages.has(Stage::kAnatomy) && layers.has_muscles) {
    b->muscles = c.raw(muscle::muscle_state_bytes(layers.muscles));
    if (layers.has_skin) b->skin = c.raw(elastic_skin::skin_state_bytes(layers.skin));
  }
  const uint32_t barnet_count = o.stages.has(Stage::kBarnet) ? layers.barnet_count : 0;
  for (uint32_t i = 0; i < barnet_count; ++i) b->barnet[i] = c.raw(barnet::barnet_state_bytes(layers.barnet[i]));
  p->flexed = c.take<int32_t>(sph_count > 0 ? rig.input_count : 0);
  p->bent = c.take<skeleton::LocalPose>(sph_count > 0 ? rig.joint_count() : 0);
  p->measured = c.take<int32_t>(rig.input_count + layers.external_count());
  // Sizes from the options, never from the blocks (null when only counting).
  const bool metaballs_on = o.stages.has(Stage::kMetaballs) && layers.has_metaballs;
  const bool skin_on = o.stages.has(Stage::kAnatomy) && layers.has_muscles && layers.has_skin;
  const bool displaced = sph_count > 0 || metaballs_on || skin_on || barnet_count > 0;
  const size_t wrap = barnet_count > 0 ? largest_barnet_wrap(layers) : 0;
  for (int a = 0; a < 3; ++a) {
    p->reference[a] = c.take<fx::Len>(displaced ? n : 0);
    p->scratch[a] = c.take<fx::Len>(std::max(metaballs_on ? n : size_t{0}, wrap));
    p->barnet_nodes[a] = c.take<fx::Len>(barnet_count > 0 ? largest_barnet_nodes(layers) : 0);
  }
  return c;
}

// out = out + (layer - reference), saturated: the superposition rule.
void add_displacement(Pipeline* p, int axis, uint32_t v, fx::Len layer) {
  fx::Len& out = p->engine.vertices.position[axis][v];
  const int64_t sum = int64_t{out} + (int64_t{layer} - p->reference[axis][v]);
  const int32_t clamped = fx::sat_i32(sum);
  if (clamped != sum) ++p->saturated;
  out = clamped;
}

PipelineStatus run_skinning(Pipeline* p, std::span<const int32_t> inputs) {
  if (!engine::engine_step(&p->engine, inputs.first(p->rig->input_count)))
    return fail(PipelineError::kBadInput, "skinning", "engine step refused its inputs");
  if (!p->reference[0].empty())
    for (int a = 0; a < 3; ++a)
      std::copy_n(p->engine.vertices.position[a].begin(), p->reference[a].size(), p->reference[a].begin());
  return {};
}

PipelineStatus run_sph(Pipeline* p, std::span<const int32_t> inputs) {
  const rig::Rig& rig = *p->rig;
  PipelineStatus first;
  // The particles were initialised at the rest pose; the first commanded pose
  // may be far from it: start them at rest in that pose, not with a jump.
  for (uint32_t i = 0; i < p->sph_count; ++i) {
    const SphJointLayer& layer = p->layers->sph[i];
    sph::SphInputs in;
    in.transforms = p->engine.model;
    in.tresca = p->options.tresca;
    in.joint_measured = p->options.sph_joint_measured;
    if (layer.force_input != kNoExternalInput &&
        !sph::sph_flexion_force(p->sph_model[i], p->engine.model, inputs[rig.input_count + layer.force_input],
                                &in.force))
      in.force = {0, 0, 0};
    if (!p->sph_started && !sph::sph_reset(&p->sph[i], p->engine.model).ok() && first.ok())
      first = fail(PipelineError::kLayer, "sph", "reset failed", i);
    const sph::SphStatus st = sph::sph_step(&p->sph[i], in);
    if (!st.ok() && first.ok()) first = fail(PipelineError::kLayer, "sph", st.message, i);
  }
  p->sph_started = true;
  // The particles' bends flex the driven joints (docs/sph.md).
  if (!p->pose_driven) {
    // Commanded DOFs: the bend adds to the driven DOF, saturated at the
    // angle range rather than wrapped: past its limit the engine clamps the
    // joint and flags it; a wrapped angle would swing it back.
    std::copy_n(inputs.begin(), p->flexed.size(), p->flexed.begin());
    for (uint32_t i = 0; i < p->sph_count; ++i) {
      const uint32_t driven = rig.joints[p->layers->sph[i].model.joint.distal_joint].first_input;
      const int64_t bent = int64_t{p->flexed[driven]} + static_cast<int32_t>(p->sph[i].bend);
      p->flexed[driven] = static_cast<int32_t>(std::clamp<int64_t>(bent, INT32_MIN, INT32_MAX));
    }
    engine::engine_step(&p->engine, p->flexed);
  } else {
    // A sampled pose: the bend turns the driven joint's local rotation about
    // the SPH axis (in that joint's frame), after the sampled rotation.
    std::copy(p->engine.locals.begin(), p->engine.locals.end(), p->bent.begin());
    for (uint32_t i = 0; i < p->sph_count; ++i) {
      const sph::SphJoint& joint = p->layers->sph[i].model.joint;
      skeleton::LocalPose& l = p->bent[joint.distal_joint];
      l.rotation = fx::mul(l.rotation, fx::quat_from_axis_angle(joint.axis, p->sph[i].bend));
    }
    engine::engine_step_locals(&p->engine, p->bent);
  }
  if (!p->reference[0].empty())
    for (int a = 0; a < 3; ++a)
      std::copy_n(p->engine.vertices.position[a].begin(), p->reference[a].size(), p->reference[a].begin());
  for (uint32_t i = 0; i < p->sph_count; ++i) sph::sph_apply_skin(p->sph[i], p->engine.vertices.position);
  return first;
}

PipelineStatus run_metaballs(Pipeline* p) {
  skin::SkinnedVertices out;
  for (int a = 0; a < 3; ++a) out.position[a] = p->scratch[a].first(p->rig->vertex_count());
  const metaballs::Status st = metaballs::step(&p->metaballs, p->engine.model, out);
  if (!st.ok()) return fail(PipelineError::kLayer, "metaballs", st.message);
  for (int a = 0; a < 3; ++a)
    for (uint32_t v = 0; v < p->rig->vertex_count(); ++v) add_displacement(p, a, v, p->scratch[a][v]);
  return {};
}

PipelineStatus run_barnet(Pipeline* p, std::span<const int32_t> inputs) {
  PipelineStatus first;
  for (uint32_t i = 0; i < p->barnet_count; ++i) {
    const barnet::BarnetModel& m = p->layers->barnet[i];
    barnet::StepOutputs out;
    for (int a = 0; a < 3; ++a) {
      out.node[a] = p->barnet_nodes[a];
      out.skin[a] = p->scratch[a];
    }
    const barnet::Status st = barnet::barnet_step(
        &p->barnet[i], {p->engine.model, inputs.first(p->rig->input_count), inputs.subspan(p->rig->input_count)}, out);
    if (!st.ok()) {
      if (first.ok()) first = fail(PipelineError::kLayer, "barnet", st.message, i);
      continue;
    }
    for (size_t k = 0; k < m.wrap.size(); ++k)
      for (int a = 0; a < 3; ++a) add_displacement(p, a, m.wrap[k].vertex, p->scratch[a][k]);
  }
  return first;
}

// An acceleration input (Q16.16 m/s^2) in the skin's Q24.8 rig units / s^2:
// one rig unit is 2^length_exponent m, so the value shifts right by
// 8 + length_exponent (rounded half up, or left and saturated).
int32_t rig_acceleration(int32_t q16_metres, int32_t length_exponent) {
  const int shift = 16 - elastic_skin::kAccelFracBits + length_exponent;  // -8..24
  if (shift > 0) return fx::sat_i32(fx::round_shift(q16_metres, shift));
  return fx::sat_i32(int64_t{q16_metres} * (int64_t{1} << -shift));
}

PipelineStatus run_anatomy(Pipeline* p, std::span<const int32_t> inputs) {
  const muscle::LayerStatus ms = muscle::muscle_step(p->layers->muscles, p->engine.model, &p->muscles);
  if (!ms.ok()) return fail(PipelineError::kLayer, "muscles", ms.message);
  if (!p->layers->has_skin) return {};
  elastic_skin::SkinModel model = p->layers->skin;
  if (p->options.skin_iterations != 0) model.params.iterations = p->options.skin_iterations;
  // The dynamic skin's time step: the loop's rate, else the rate the rig
  // was built for, else rigc's default rate (1 kHz).
  elastic_skin::SkinTick tick;
  tick.tick_hz = p->options.tick_hz != 0 ? p->options.tick_hz : (p->layers->rate_hz != 0 ? p->layers->rate_hz : 1000);
  // The base's measured acceleration (LEMAN §3: the skin feels -a_base).
  int32_t base[3] = {0, 0, 0};
  for (int c = 0; c < 3; ++c) {
    const uint32_t k = p->layers->skin_base_acceleration[c];
    if (k != kNoExternalInput) base[c] = rig_acceleration(inputs[p->rig->input_count + k], p->rig->length_exponent);
  }
  tick.base_acceleration = {base[0], base[1], base[2]};
  const uint32_t cap = std::min<uint32_t>(p->options.skin_max_anchor_acceleration, 32767);
  tick.max_anchor_acceleration = rig_acceleration(static_cast<int32_t>(cap << 16), p->rig->length_exponent);
  const muscle::LayerStatus ss =
      elastic_skin::skin_step(model, p->layers->muscles, p->muscles, p->engine.model, tick, &p->skin);
  if (!ss.ok()) return fail(PipelineError::kLayer, "elastic skin", ss.message);
  const std::span<const uint32_t> region = p->layers->skin_region;
  if (region.empty()) {
    for (int a = 0; a < 3; ++a)
      for (uint32_t v = 0; v < model.vertex_count; ++v) add_displacement(p, a, v, p->skin.position[a][v]);
    return {};
  }
  // The support region: weight x (relaxed - reference), Q2.30 weights.
  for (size_t i = 0; i < region.size(); ++i) {
    const uint32_t v = region[i];
    const fx::Unit w = p->layers->skin_region_weight[i];
    for (int a = 0; a < 3; ++a) {
      const int64_t delta = int64_t{p->skin.position[a][v]} - p->reference[a][v];
      add_displacement(p, a, v, fx::sat_i32(p->reference[a][v] + fx::round_shift(delta * w, fx::kUnitFracBits)));
    }
  }
  return {};
}

}  // namespace

const char* stage_name(Stage s) {
  const uint32_t i = static_cast<uint32_t>(s);
  return i < kStageCount ? kStages[i].name : "unknown";
}

size_t pipeline_state_bytes(const rig::Rig& rig, const LayerSet& layers, const PipelineOptions& options) {
  Pipeline probe;
  Blocks blocks;
  return layout(rig, layers, options, nullptr, 0, &probe, &blocks).needed();
}

PipelineStatus sph_gains_for_rate(const sph::SphParams& c, uint32_t compiled_hz, uint32_t tick_hz,
                                  sph::SphParams* out) {
  *out = c;
  if (tick_hz == 0 || tick_hz == compiled_hz) return {};
  const uint32_t substeps = sph::substeps_for_rate(tick_hz);
  if (substeps > sph::kMaxSubsteps)
    return fail(PipelineError::kBadModel, "sph", "the loop rate needs more than 16 substeps (at least 13 Hz)");
  const int64_t num = int64_t{compiled_hz} * c.substeps, den = int64_t{tick_hz} * substeps;
  // v x N / D, rounded half up. At the rates rigc writes (13..100000 Hz)
  // v N < 2^53; the header's rate_hz is any u32 (N < 2^36) and the second
  // scaling takes the first's result, so a product beyond int64 saturates to
  // INT64_MAX: outside every gain's range (refused below; the load gain
  // saturates at its Q2.30 limit).
  const int64_t limit = num > 0 ? (INT64_MAX - den) / num : INT64_MAX;
  const auto scale = [num, den, limit](int64_t v) -> int64_t {
    if (v > limit || v < -limit) return v > 0 ? INT64_MAX : INT64_MIN;
    return (v * num + den / 2) / den;
  };
  const auto gain = [](int64_t v, const char* name, fx::Unit* g) {
    if (v < 0 || v >= fx::kUnitOne) return fail(PipelineError::kBadModel, "sph", name);
    *g = static_cast<fx::Unit>(v);
    return PipelineStatus{};
  };
  PipelineStatus st;
  out->substeps = substeps;
  if (!(st = gain(scale(scale(c.elastic_gain)), "elastic gain k_e dt^2 out of [0, 1) at this rate", &out->elastic_gain))
           .ok() ||
      !(st = gain(scale(scale(c.pressure_gain)), "pressure gain out of [0, 1) at this rate", &out->pressure_gain))
           .ok() ||
      !(st = gain(scale(c.viscosity_gain), "viscosity gain mu dt out of [0, 1) at this rate", &out->viscosity_gain))
           .ok() ||
      !(st = gain(scale(scale(c.tension_gain)), "tension gain (sigma dt^2) out of [0, 1) at this rate",
                  &out->tension_gain))
           .ok())
    return st;
  // The load gain (dt^2 / (m unit), Q2.30) saturates at 2.0 as rigc's builder
  // saturates it: a long tick on a light tissue.
  out->load_gain = fx::sat_i32(scale(scale(c.load_gain)));
  const int64_t loss = scale(int64_t{fx::kUnitOne} - c.damping);
  if (loss < 0 || loss >= fx::kUnitOne)
    return fail(PipelineError::kBadModel, "sph", "damping c dt out of [0, 1) at this rate");
  out->damping = static_cast<fx::Unit>(fx::kUnitOne - loss);
  return {};
}

PipelineStatus pipeline_init(const rig::Rig& rig, const LayerSet& layers, const PipelineOptions& options, void* arena,
                             size_t arena_bytes, Pipeline* out) {
  if (out == nullptr) return fail(PipelineError::kArena, "pipeline", "no pipeline to initialise");
  if (!fx::aligned8(arena)) return fail(PipelineError::kArena, "pipeline", "arena missing or misaligned");
  if (options.skin_iterations > elastic_skin::kMaxIterations)
    return fail(PipelineError::kBadModel, "pipeline", "skin_iterations beyond the elastic skin's maximum (256)");
  // Built in place: the layer states keep pointers to p.sph_model.
  Pipeline& p = *out;
  p = Pipeline{};
  p.rig = &rig;
  p.layers = &layers;
  p.options = options;
  Blocks b;
  const fx::ArenaCarver c = layout(rig, layers, options, arena, arena_bytes, &p, &b);
  if (c.failed()) return fail(PipelineError::kArena, "pipeline", "arena smaller than pipeline_state_bytes");
  if (!engine::engine_init(rig, b.engine, engine::engine_arena_bytes(rig), &p.engine))
    return fail(PipelineError::kArena, "skinning", "engine arena");
  p.input_count = rig.input_count + layers.external_count();
  p.sph_count = options.stages.has(Stage::kSph) ? layers.sph_count : 0;
  for (uint32_t i = 0; i < p.sph_count; ++i) {
    p.sph_model[i] = layers.sph[i].model;
    PipelineStatus rate =
        sph_gains_for_rate(layers.sph[i].model.params, layers.rate_hz, options.tick_hz, &p.sph_model[i].params);
    if (!rate.ok()) return rate;
    const sph::SphModel& m = p.sph_model[i];
    sph::SphStatus st = sph::sph_validate(m, rig.joint_count(), rig.vertex_count());
    if (st.ok()) st = sph::sph_init(m, p.engine.model, b.sph[i], sph::sph_state_bytes(m), &p.sph[i]);
    if (!st.ok()) return fail(PipelineError::kBadModel, "sph", st.message, i);
  }
  p.metaballs_on = b.metaballs != nullptr;
  if (p.metaballs_on) {
    metaballs::Status st =
        metaballs::init(layers.metaballs, b.metaballs, metaballs::state_bytes(layers.metaballs), &p.metaballs);
    // Physical jiggle gains are converted from the section's rate to the
    // loop's (as SPH's gains are above).
    if (st.ok() && options.tick_hz != 0) st = metaballs::set_tick_rate(&p.metaballs, options.tick_hz);
    if (!st.ok()) return fail(PipelineError::kBadModel, "metaballs", st.message);
  }
  p.anatomy_on = b.muscles != nullptr;
  if (p.anatomy_on) {
    muscle::LayerStatus st =
        muscle::muscle_state_init(layers.muscles, b.muscles, muscle::muscle_state_bytes(layers.muscles), &p.muscles);
    if (st.ok() && layers.has_skin)
      st = elastic_skin::skin_state_init(layers.skin, b.skin, elastic_skin::skin_state_bytes(layers.skin), &p.skin);
    if (!st.ok()) return fail(PipelineError::kBadModel, "anatomy", st.message);
  }
  p.barnet_count = options.stages.has(Stage::kBarnet) ? layers.barnet_count : 0;
  for (uint32_t i = 0; i < p.barnet_count; ++i) {
    const barnet::Status st =
        barnet::barnet_init(layers.barnet[i], b.barnet[i], barnet::barnet_state_bytes(layers.barnet[i]), &p.barnet[i]);
    if (!st.ok()) return fail(PipelineError::kBadModel, "barnet", st.message, i);
  }
  return {};
}

bool pipeline_stage_on(const Pipeline& p, Stage s) {
  switch (s) {
    case Stage::kSkinning:
      return true;
    case Stage::kSph:
      return p.sph_count > 0;
    case Stage::kMetaballs:
      return p.metaballs_on;
    case Stage::kBarnet:
      return p.barnet_count > 0;
    case Stage::kAnatomy:
      return p.anatomy_on;
  }
  return false;
}

namespace {

// Twist of q about a unit axis: 2 atan2(q.v . axis, q.w), a binary angle.
fx::Angle twist_angle(const fx::Quat& q, const fx::Unit axis[3]) {
  const int64_t along = int64_t{q.x} * axis[0] + int64_t{q.y} * axis[1] + int64_t{q.z} * axis[2];
  const int32_t y = fx::sat_i32(fx::round_shift(along, fx::kUnitFracBits));
  return static_cast<fx::Angle>(2u * fx::atan2_angle(y, q.w));
}

void measure_dofs(Pipeline* p) {
  const rig::Rig& rig = *p->rig;
  for (uint32_t j = 0; j < rig.joint_count(); ++j) {
    const rig::JointRecord& r = rig.joints[j];
    const skeleton::LocalPose& l = p->engine.locals[j];
    const fx::Quat rest{r.rest_rotation[0], r.rest_rotation[1], r.rest_rotation[2], r.rest_rotation[3]};
    const fx::Quat relative = fx::mul(fx::conjugate(rest), l.rotation);
    for (uint32_t d = 0; d < r.dof_count; ++d) {
      int32_t value = 0;
      if (r.dof_kind == static_cast<uint8_t>(rig::DofKind::kRotation)) {
        value = static_cast<int32_t>(twist_angle(relative, r.dof_axis[d]));
      } else {
        const int64_t offset = (int64_t{l.translation.x} - r.rest_translation[0]) * r.dof_axis[d][0] +
                               (int64_t{l.translation.y} - r.rest_translation[1]) * r.dof_axis[d][1] +
                               (int64_t{l.translation.z} - r.rest_translation[2]) * r.dof_axis[d][2];
        value = fx::sat_i32(fx::round_shift(offset, fx::kUnitFracBits));
      }
      p->measured[r.first_input + d] = value;
    }
  }
}

}  // namespace

namespace {

PipelineStatus run_stage(Pipeline* p, Stage s, std::span<const int32_t> inputs) {
  switch (s) {
    case Stage::kSkinning:
      return run_skinning(p, inputs);
    case Stage::kSph:
      return run_sph(p, inputs);
    case Stage::kMetaballs:
      return run_metaballs(p);
    case Stage::kBarnet:
      return run_barnet(p, inputs);
    case Stage::kAnatomy:
      return run_anatomy(p, inputs);
  }
  return {};
}

uint64_t probe_now(const StepProbe* probe) {
  return probe != nullptr && probe->now_ns != nullptr ? probe->now_ns(probe->context) : 0;
}

void stage_done(const StepProbe* probe, StepReport* report, Stage s, uint64_t started, const Pipeline& p) {
  if (report != nullptr) {
    report->ran.set(s, true);
    if (probe != nullptr && probe->now_ns != nullptr)
      report->stage_ns[static_cast<uint32_t>(s)] = probe->now_ns(probe->context) - started;
  }
  if (probe != nullptr && probe->after_stage != nullptr) probe->after_stage(probe->context, s, p);
}

// Stages first..last that are on, in order; the first failure ends the tick.
PipelineStatus run_stages(Pipeline* p, std::span<const int32_t> inputs, Stage first, const StepProbe* probe,
                          StepReport* report) {
  for (uint32_t i = static_cast<uint32_t>(first); i < kStageCount; ++i) {
    const auto s = static_cast<Stage>(i);
    if (!pipeline_stage_on(*p, s)) continue;
    const uint64_t started = probe_now(probe);
    const PipelineStatus st = run_stage(p, s, inputs);
    stage_done(probe, report, s, started, *p);
    if (!st.ok()) return st;
  }
  return {};
}

void begin_report(StepReport* report) {
  if (report == nullptr) return;
  for (uint64_t& ns : report->stage_ns) ns = 0;
  report->ran = StageSet::none();
  std::fill(report->input_flags.begin(), report->input_flags.end(), uint8_t{0});
}

// The engine's clamp flags per joint and the SPH joints' yield, per input.
void report_input_flags(const Pipeline& p, StepReport* report) {
  if (report == nullptr || report->input_flags.empty()) return;
  const std::span<uint8_t> flags = report->input_flags;
  const rig::Rig& rig = *p.rig;
  for (uint32_t j = 0; j < rig.joint_count(); ++j) {
    if ((p.engine.joint_flags[j] & skeleton::kJointClamped) == 0) continue;
    const rig::JointRecord& r = rig.joints[j];
    for (uint32_t d = 0; d < r.dof_count; ++d)
      if (r.first_input + d < flags.size()) flags[r.first_input + d] |= kInputClamped;
  }
  for (uint32_t i = 0; i < p.sph_count; ++i) {
    if (!p.sph[i].joint_yielded) continue;
    const uint32_t input = rig.joints[p.layers->sph[i].model.joint.distal_joint].first_input;
    if (input < flags.size()) flags[input] |= kInputYielded;
  }
}

}  // namespace

PipelineStatus pipeline_step(Pipeline* p, std::span<const int32_t> inputs, const StepProbe* probe, StepReport* report) {
  begin_report(report);
  if (p == nullptr || p->rig == nullptr) return fail(PipelineError::kArena, "pipeline", "not initialised");
  if (inputs.size() < p->input_count)
    return fail(PipelineError::kBadInput, "pipeline", "fewer inputs than the rig's and its external inputs");
  p->saturated = 0;
  p->pose_driven = false;
  const PipelineStatus st = run_stages(p, inputs, Stage::kSkinning, probe, report);
  report_input_flags(*p, report);
  return st;
}

PipelineStatus pipeline_step_locals(Pipeline* p, std::span<const skeleton::LocalPose> locals,
                                    std::span<const int32_t> external, const StepProbe* probe, StepReport* report) {
  begin_report(report);
  if (p == nullptr || p->rig == nullptr) return fail(PipelineError::kArena, "pipeline", "not initialised");
  // The skinning stage: the pose from the locals, the DOFs measured from it.
  const uint64_t started = probe_now(probe);
  if (!engine::engine_step_locals(&p->engine, locals))
    return fail(PipelineError::kBadInput, "skinning", "one local pose per joint is needed");
  p->pose_driven = true;
  p->saturated = 0;
  measure_dofs(p);
  const uint32_t rig_inputs = p->rig->input_count;
  for (uint32_t i = rig_inputs; i < p->input_count; ++i)
    p->measured[i] = i - rig_inputs < external.size() ? external[i - rig_inputs] : 0;
  if (!p->reference[0].empty())
    for (int a = 0; a < 3; ++a)
      std::copy_n(p->engine.vertices.position[a].begin(), p->reference[a].size(), p->reference[a].begin());
  stage_done(probe, report, Stage::kSkinning, started, *p);
  const PipelineStatus st = run_stages(p, p->measured, Stage::kSph, probe, report);
  p->pose_driven = false;
  report_input_flags(*p, report);
  return st;
}

}  // namespace sinew::pipeline
