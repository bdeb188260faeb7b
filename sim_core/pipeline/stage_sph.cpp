// The SPH stage (sph-elastic-joints-tresca; docs/sph.md): every SPH joint
// steps on the commanded pose, their bends flex the driven joints, the
// skeleton and skin are recomputed once with them (the new reference), then
// each joint adds its eq. (2) offsets.
#include <algorithm>

#include "sim_core/fixed/arena.hpp"
#include "sim_core/fixed/quat.hpp"
#include "sim_core/sph/sph_step.hpp"
#include "stage_fns.hpp"
#include "stage_sph_rate.hpp"

namespace sinew::pipeline {

bool* sph_tresca_option(PipelineOptions* o) { return &o->sph.tresca; }
bool* sph_joint_measured_option(PipelineOptions* o) { return &o->sph.joint_measured; }
bool* sph_measured_from_sources_option(PipelineOptions* o) { return &o->sph.measured_from_sources; }

PipelineStatus sph_gains_for_rate(const sph::SphParams& c, uint32_t compiled_hz, uint32_t tick_hz,
                                  sph::SphParams* out) {
  using stages::stage_fail;
  *out = c;
  if (tick_hz == 0 || tick_hz == compiled_hz) return {};
  const uint32_t substeps = sph::substeps_for_rate(tick_hz);
  if (substeps > sph::kMaxSubsteps)
    return stage_fail(PipelineError::kBadModel, "sph", "the loop rate needs more than 16 substeps (at least 13 Hz)");
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
    if (v < 0 || v >= fx::kUnitOne) return stage_fail(PipelineError::kBadModel, "sph", name);
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
    return stage_fail(PipelineError::kBadModel, "sph", "damping c dt out of [0, 1) at this rate");
  out->damping = static_cast<fx::Unit>(fx::kUnitOne - loss);
  return {};
}

namespace stages {
namespace {

// A joint's name (NUL-terminated within kNameBytes by the loader), or jointN.
void joint_name(const rig::Rig& rig, uint32_t j, rig::MessageBuilder* out) {
  if (rig.names.empty() || j >= rig.names.size()) {
    out->text("joint").unsigned_number(j);
    return;
  }
  char name[rig::kNameBytes + 1] = {};
  for (uint32_t k = 0; k < rig::kNameBytes && rig.names[j][k] != '\0'; ++k) name[k] = rig.names[j][k];
  out->text(name);
}

}  // namespace

uint32_t sph_compiled(const LayerSet& layers) { return layers.sph.count; }

// The bends go into flexed inputs (bent locals for pose-driven steps); the
// skin they recompute becomes R.
SharedNeeds sph_shares(const rig::Rig&, const LayerSet&) { return {.reference = true, .bent_pose = true}; }

void sph_describe(const rig::Rig& rig, const LayerSet& layers, rig::MessageBuilder* out) {
  for (uint32_t i = 0; i < layers.sph.count; ++i) {
    if (i > 0) out->text(" ");
    out->text("sph(");
    joint_name(rig, layers.sph.joint[i].model.joint.distal_joint, out);
    out->text(")");
  }
}

PipelineStatus sph_validate(const rig::Rig& rig, const LayerSet& layers) {
  for (uint32_t i = 0; i < layers.sph.count; ++i) {
    const layer::LayerStatus st = sph::sph_validate(layers.sph.joint[i].model, rig);
    if (!st.ok()) return stage_fail(PipelineError::kBadModel, "sph", st.message, i);
  }
  return {};
}

// The state size does not depend on the gains (nor on the rate).
size_t sph_state_bytes(const rig::Rig&, const LayerSet& layers, const PipelineOptions&) {
  fx::ArenaCarver c(nullptr, 0);
  for (uint32_t i = 0; i < layers.sph.count; ++i) c.raw(sph::sph_state_bytes(layers.sph.joint[i].model));
  return c.needed();
}

PipelineStatus sph_init(Pipeline* p, uint8_t* block, size_t bytes) {
  const LayerSet& layers = *p->layers;
  fx::ArenaCarver c(block, bytes);
  p->sph.count = layers.sph.count;
  for (uint32_t i = 0; i < p->sph.count; ++i) {
    // The states keep pointers to p->sph.model: the gains for the loop's rate.
    p->sph.model[i] = layers.sph.joint[i].model;
    const PipelineStatus rate = sph_gains_for_rate(layers.sph.joint[i].model.params, layers.rate_hz, p->options.tick_hz,
                                                   &p->sph.model[i].params);
    if (!rate.ok()) return rate;
    const sph::SphModel& m = p->sph.model[i];
    const size_t need = sph::sph_state_bytes(m);
    layer::LayerStatus st = sph::sph_validate(m, *p->rig);
    if (st.ok()) st = sph::sph_init(m, p->engine.model, c.raw(need), need, &p->sph.joint[i]);
    if (!st.ok()) return stage_fail(PipelineError::kBadModel, "sph", st.message, i);
  }
  return {};
}

PipelineStatus sph_step(Pipeline* p, std::span<const int32_t> inputs) {
  const rig::Rig& rig = *p->rig;
  PipelineStatus first;
  // The particles were initialised at the rest pose; the first commanded pose
  // may be far from it: start them at rest in that pose, not with a jump.
  for (uint32_t i = 0; i < p->sph.count; ++i) {
    const SphJointLayer& layer = p->layers->sph.joint[i];
    sph::SphInputs in;
    in.transforms = p->engine.model;
    in.tresca = p->options.sph.tresca;
    in.workers = p->options.workers;  // the search and the per-particle loops
    // Measured when the run says every SPH joint is ([layers] sph_joint =
    // "measured"), or when a source measures this joint's driven DOF (unless
    // [layers] sph_measured_from_sources = false): a
    // glove's elbow sensor already shows the load's flexion, so the bend is
    // not added twice (docs/sph.md, "Measured and simulated joints").
    const uint32_t driven = rig.joints[layer.model.joint.distal_joint].first_input;
    const std::span<const uint8_t> measured = p->engine.measured_inputs;
    in.joint_measured = p->options.sph.joint_measured ||
                        (p->options.sph.measured_from_sources && driven < measured.size() && measured[driven] != 0);
    if (layer.force_input != kNoExternalInput &&
        !sph::sph_flexion_force(p->sph.model[i], p->engine.model, inputs[rig.input_count + layer.force_input],
                                &in.force))
      in.force = {0, 0, 0};
    if (!p->sph.started && !sph::sph_reset(&p->sph.joint[i], p->engine.model).ok() && first.ok())
      first = stage_fail(PipelineError::kLayer, "sph", "reset failed", i);
    const layer::LayerStatus st = sph::sph_step(&p->sph.joint[i], in);
    if (!st.ok() && first.ok()) first = stage_fail(PipelineError::kLayer, "sph", st.message, i);
  }
  p->sph.started = true;
  // The particles' bends flex the driven joints (docs/sph.md).
  if (!p->pose_driven) {
    // Commanded DOFs: the bend adds to the driven DOF, saturated at the
    // angle range rather than wrapped: past its limit the engine clamps the
    // joint and flags it; a wrapped angle would swing it back.
    std::copy_n(inputs.begin(), p->flexed.size(), p->flexed.begin());
    for (uint32_t i = 0; i < p->sph.count; ++i) {
      const uint32_t driven = rig.joints[p->layers->sph.joint[i].model.joint.distal_joint].first_input;
      const int64_t bent = int64_t{p->flexed[driven]} + static_cast<int32_t>(p->sph.joint[i].bend);
      p->flexed[driven] = static_cast<int32_t>(std::clamp<int64_t>(bent, INT32_MIN, INT32_MAX));
    }
    engine::engine_step(&p->engine, p->flexed);
  } else {
    // A sampled pose: the bend turns the driven joint's local rotation about
    // the SPH axis (in that joint's frame), after the sampled rotation.
    std::copy(p->engine.locals.begin(), p->engine.locals.end(), p->bent.begin());
    for (uint32_t i = 0; i < p->sph.count; ++i) {
      const sph::SphJoint& joint = p->layers->sph.joint[i].model.joint;
      skeleton::LocalPose& l = p->bent[joint.distal_joint];
      l.rotation = fx::mul(l.rotation, fx::quat_from_axis_angle(joint.axis, p->sph.joint[i].bend));
    }
    engine::engine_step_locals(&p->engine, p->bent);
  }
  take_reference(p);
  for (uint32_t i = 0; i < p->sph.count; ++i) sph::sph_apply_skin(p->sph.joint[i], p->engine.vertices.position);
  return first;
}

// A joint that yielded (Tresca, eqs. (3)-(4)) flags its driven input.
void sph_flag_inputs(const Pipeline& p, std::span<uint8_t> flags) {
  for (uint32_t i = 0; i < p.sph.count; ++i) {
    if (!p.sph.joint[i].joint_yielded) continue;
    const uint32_t input = p.rig->joints[p.layers->sph.joint[i].model.joint.distal_joint].first_input;
    if (input < flags.size()) flags[input] |= kInputYielded;
  }
}

}  // namespace stages
}  // namespace sinew::pipeline
