#include "state.hpp"

#include "jiggle_gains.hpp"
#include "kernels.hpp"
#include "sim_core/fixed/arena.hpp"
#include "sim_core/rig/message.hpp"
#include "validate.hpp"

namespace sinew::metaballs {
namespace {

using Carver = fx::ArenaCarver;

Carver layout(const MetaballModel& m, uint8_t* base, size_t size, MetaballState* s) {
  Carver c(base, size);
  const size_t nb = m.ball_count();
  s->bone = c.take<fx::Mat34>(m.joint_count);
  s->bone_rotation = c.take<fx::Quat>(m.joint_count);
  s->ball_center = c.take<fx::Vec3>(nb);
  s->ball_previous = c.take<fx::Vec3>(nb);
  s->ball_target = c.take<fx::Vec3>(nb);
  s->ball_last_target = c.take<fx::Vec3>(nb);
  s->ball_last_step = c.take<fx::Vec3>(nb);
  const size_t jiggle = m.jiggle_rate_hz != 0 ? nb : 0;
  s->jiggle_stiffness = c.take<fx::Unit>(jiggle);
  s->jiggle_damping = c.take<fx::Unit>(jiggle);
  s->pair_coupling = c.take<fx::Unit>(m.jiggle_rate_hz != 0 ? m.pairs.size() : 0);
  s->ball_pull = c.take<int64_t>(3 * jiggle);
  s->swing_fraction = c.take<int64_t>(3 * jiggle);
  s->swing_previous = c.take<int64_t>(3 * jiggle);
  s->action_point = c.take<fx::Vec3>(m.action_balls.size());
  s->ball_rotation = c.take<fx::Rot3>(nb);
  s->ball_quat = c.take<fx::Quat>(nb);
  s->ball_frame = c.take<fx::DualQuat>(nb);
  s->ball_scale = c.take<fx::Unit>(nb);
  s->ball_touching = c.take<uint8_t>(nb);
  s->vertex_rest_centre = c.take<fx::Vec3>(m.vertex_count);
  s->vertex_rest_disp = c.take<fx::Vec3>(m.vertex_count);
  s->vertex_bone = c.take<uint16_t>(m.vertex_count);
  const uint32_t candidates = detail::shared_frame_candidates(m);
  s->vertex_frame = c.take<uint32_t>(m.vertex_count);
  s->frame_vertex = c.take<uint32_t>(candidates);
  s->shared_frame = c.take<detail::NormalBallFrame>(candidates);
  s->frame_table = c.take<uint32_t>(detail::shared_frame_table_size(candidates));
  s->jv_posed_laplacian = c.take<fx::Vec3>(m.jv_count());
  s->jv_scratch = c.take<fx::Vec3>(m.jv_count());
  return c;
}

}  // namespace

size_t metaballs_state_bytes(const MetaballModel& model) {
  MetaballState probe;
  return layout(model, nullptr, 0, &probe).needed();
}

LayerStatus metaballs_init(const MetaballModel& model, void* memory, size_t bytes, MetaballState* out) {
  LayerStatus s = metaballs_validate_model(model);
  if (!s.ok()) return s;
  const auto arena_error = [&](const char* problem) {
    s.error = LayerError::kArena;
    rig::MessageBuilder(s.message, sizeof(s.message)).text("state memory: ").text(problem);
    return s;
  };
  if (out == nullptr) return arena_error("no state given");
  if (memory == nullptr || (reinterpret_cast<uintptr_t>(memory) & 7u) != 0)
    return arena_error("null or not 8-byte aligned");
  MetaballState st;
  st.model = &model;
  if (layout(model, static_cast<uint8_t*>(memory), bytes, &st).failed())
    return arena_error("smaller than metaballs_state_bytes(model)");
  for (uint32_t b = 0; b < model.ball_count(); ++b) {
    st.ball_center[b] = st.ball_previous[b] = st.ball_target[b] = st.ball_last_target[b] = model.ball_rest[b];
    st.ball_last_step[b] = {0, 0, 0};
    st.ball_scale[b] = fx::kUnitOne;
    st.ball_touching[b] = 0;
    st.ball_quat[b] = fx::quat_identity();
  }
  for (size_t i = 0; i < st.swing_fraction.size(); ++i) st.swing_fraction[i] = st.swing_previous[i] = 0;
  for (size_t b = 0; b < st.jiggle_stiffness.size(); ++b) {
    st.jiggle_stiffness[b] = model.ball_jiggle[b];
    st.jiggle_damping[b] = model.jiggle_damping;
  }
  for (size_t p = 0; p < st.pair_coupling.size(); ++p) st.pair_coupling[p] = model.pairs[p].stiffness;
  detail::make_rest_blends(model, &st);
  detail::make_shared_frame_index(model, &st);
  st.tick_hz = model.jiggle_rate_hz;
  if (!detail::coupling_stable(model, &st, model.jiggle_rate_hz)) {
    s.error = LayerError::kBadValue;
    rig::MessageBuilder(s.message, sizeof(s.message)).text("pairs: coupling springs unstable at the model's rate");
    return s;
  }
  *out = st;
  return s;
}

LayerStatus set_tick_rate(MetaballState* s, uint32_t tick_hz) {
  LayerStatus st;
  if (s == nullptr || s->model == nullptr) {
    st.error = LayerError::kNotReady;
    rig::MessageBuilder(st.message, sizeof(st.message)).text("state: not initialised (call metaballs::init)");
    return st;
  }
  const MetaballModel& m = *s->model;
  const auto refuse = [&](const char* problem) {
    st.error = LayerError::kBadValue;
    rig::MessageBuilder(st.message, sizeof(st.message))
        .text("tick_hz ")
        .unsigned_number(tick_hz)
        .text(": ")
        .text(problem)
        .text(" (jiggle gains built for ")
        .unsigned_number(m.jiggle_rate_hz)
        .text(" Hz)");
    return st;
  };
  if (tick_hz == 0) return refuse("no rate");
  if (m.jiggle_rate_hz == 0) return s->primed = false, st;
  // Convert every ball and pair first, then commit: a refusal leaves the
  // state as it was.
  for (uint32_t pass = 0; pass < 2; ++pass) {
    for (size_t b = 0; b < s->jiggle_stiffness.size(); ++b) {
      if (m.ball_jiggle[b] == 0) continue;
      JiggleGains g;
      if (!jiggle_gains_for_rate({m.ball_jiggle[b], m.jiggle_damping}, m.jiggle_rate_hz, tick_hz, &g))
        return refuse("cannot carry the jiggle swing");
      if (pass == 1) s->jiggle_stiffness[b] = g.stiffness, s->jiggle_damping[b] = g.damping;
    }
    for (size_t p = 0; p < s->pair_coupling.size(); ++p) {
      fx::Unit x = 0;
      if (!coupling_for_rate(m.pairs[p].stiffness, m.jiggle_rate_hz, tick_hz, &x))
        return refuse("cannot carry the coupling springs");
      if (pass == 1) s->pair_coupling[p] = x;
    }
    if (pass == 0 && !detail::coupling_stable(m, s, tick_hz)) return refuse("coupling springs unstable at this rate");
  }
  s->tick_hz = tick_hz;
  s->primed = false;
  return st;
}

}  // namespace sinew::metaballs
