#include "engine.hpp"

#include "sim_core/fixed/arena.hpp"
#include "sim_core/layer/range_totals.hpp"

namespace sinew::engine {
namespace {

using Carver = fx::ArenaCarver;

Carver layout(const rig::Rig& rig, uint8_t* base, size_t size, Engine* e) {
  Carver c(base, size);
  const size_t joints = rig.joint_count(), pal = rig.palette.size(), n = rig.vertex_count();
  e->locals = c.take<skeleton::LocalPose>(joints);
  e->joint_flags = c.take<uint8_t>(joints);
  e->model = c.take<fx::Mat34>(joints);
  e->palette = c.take<fx::Mat34>(pal);
  e->dual = rig.any_dual_quaternion ? c.take<fx::DualQuat>(pal) : std::span<fx::DualQuat>{};
  for (int i = 0; i < 3; ++i) e->vertices.position[i] = c.take<fx::Len>(n);
  for (int i = 0; i < 3; ++i)
    e->vertices.normal[i] = rig.normal[0].empty() ? std::span<fx::Unit>{} : c.take<fx::Unit>(n);
  return c;
}

void finish_step(Engine* e, const layer::Workers* workers = nullptr) {
  const rig::Rig& rig = *e->rig;
  skeleton::locals_to_model(rig, e->locals, e->model);
  skeleton::skinning_palette(rig, e->model, e->palette, e->dual);
  const auto range = [&](uint32_t begin, uint32_t end) {
    // skin_vertices writes its range from index 0 of the view it is given.
    skin::SkinnedVertices part;
    for (int c = 0; c < 3; ++c) {
      part.position[c] = e->vertices.position[c].subspan(begin, end - begin);
      if (!e->vertices.normal[c].empty()) part.normal[c] = e->vertices.normal[c].subspan(begin, end - begin);
    }
    return skin::skin_vertices(rig, e->palette, e->dual, begin, end - begin, part);
  };
  e->stats.saturated = layer::run_ranges_summed(workers, rig.vertex_count(), range);
  ++e->stats.steps;
}

}  // namespace

size_t engine_arena_bytes(const rig::Rig& rig) {
  // The same layout as engine_init, carved over no memory: only counts bytes.
  Engine probe;
  return layout(rig, nullptr, 0, &probe).needed();
}

bool engine_init(const rig::Rig& rig, void* arena, size_t arena_bytes, Engine* out) {
  if (arena == nullptr || (reinterpret_cast<uintptr_t>(arena) & 7u) != 0) return false;
  Engine e;
  e.rig = &rig;
  const Carver c = layout(rig, static_cast<uint8_t*>(arena), arena_bytes, &e);
  if (c.failed()) return false;
  skeleton::rest_locals(rig, e.locals);
  finish_step(&e);
  e.stats = {};
  *out = e;
  return true;
}

bool engine_step(Engine* e, std::span<const int32_t> inputs, const layer::Workers* workers) {
  if (e == nullptr || e->rig == nullptr || inputs.size() < e->rig->input_count) return false;
  e->stats.clamped_dofs = skeleton::dofs_to_locals(*e->rig, inputs, e->measured_inputs, e->locals, e->joint_flags);
  finish_step(e, workers);
  return true;
}

bool engine_step_locals(Engine* e, std::span<const skeleton::LocalPose> locals) {
  if (e == nullptr || e->rig == nullptr || locals.size() != e->rig->joint_count()) return false;
  for (size_t j = 0; j < locals.size(); ++j) {
    e->locals[j] = locals[j];
    e->joint_flags[j] = 0;
  }
  e->stats.clamped_dofs = 0;
  finish_step(e);
  return true;
}

}  // namespace sinew::engine
