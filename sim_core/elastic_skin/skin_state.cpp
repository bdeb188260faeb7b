#include "skin_state.hpp"

#include "sim_core/fixed/arena.hpp"

namespace sinew::elastic_skin {
namespace {

fx::ArenaCarver layout(const SkinModel& model, void* base, size_t size, SkinState* s) {
  fx::ArenaCarver c(base, size);
  const size_t n = model.vertex_count;
  for (int a = 0; a < 3; ++a) s->position[a] = c.take<fx::Len>(n);
  for (int a = 0; a < 3; ++a) s->anchor[a] = c.take<fx::Len>(n);
  for (int a = 0; a < 3; ++a) s->previous[a] = c.take<fx::Len>(n);
  for (int a = 0; a < 3; ++a) s->normal[a] = c.take<fx::Unit>(n);
  for (int a = 0; a < 3; ++a) s->force[a] = c.take<int64_t>(n);
  s->weight = c.take<int64_t>(n);
  s->max_relax = c.take<fx::Len>(kMaxIterations);
  const bool dynamic = model.solver.mode == static_cast<uint8_t>(SkinMode::kDynamic);
  const size_t dn = dynamic ? n : 0, bands = dynamic ? model.bands.size() : 0;
  for (int a = 0; a < 3; ++a) s->fine[a] = c.take<int64_t>(dn);
  for (int a = 0; a < 3; ++a) s->velocity[a] = c.take<int64_t>(dn);
  for (int a = 0; a < 3; ++a) s->anchor_start[a] = c.take<fx::Len>(dn);
  for (int a = 0; a < 3; ++a) s->anchor_step[a] = c.take<int64_t>(dn);
  for (int a = 0; a < 3; ++a) s->band_start[a] = c.take<fx::Len>(bands);
  for (int a = 0; a < 3; ++a) s->band_end[a] = c.take<fx::Len>(bands);
  const bool surface = model.solver.fat_normal == static_cast<uint8_t>(FatNormal::kSurface);
  for (int a = 0; a < 3; ++a) s->surface_normal[a] = c.take<fx::Unit>(surface ? n : 0);
  return c;
}

}  // namespace

size_t skin_state_bytes(const SkinModel& model) {
  SkinState probe;
  return layout(model, nullptr, 0, &probe).needed();
}

LayerStatus skin_init(const SkinModel& model, void* memory, size_t bytes, SkinState* out) {
  if (out == nullptr) return muscle::layer_fail(LayerError::kArena, "skin state", -1, "", "null output");
  if (model.vertex_count > kMaxVertices)
    return muscle::layer_fail(LayerError::kBadValue, "skin model", -1, "vertex_count", "above 2^20", model.vertex_count,
                              true);
  if (!fx::aligned8(memory))
    return muscle::layer_fail(LayerError::kArena, "skin state", -1, "memory", "null or not 8-byte aligned");
  SkinState s;
  if (layout(model, memory, bytes, &s).failed())
    return muscle::layer_fail(LayerError::kArena, "skin state", -1, "bytes", "smaller than skin_state_bytes",
                              static_cast<int64_t>(bytes), true);
  s.vertex_count = model.vertex_count;
  *out = s;
  return {};
}

}  // namespace sinew::elastic_skin
