#include "muscle_state.hpp"

#include "sim_core/fixed/arena.hpp"
#include "sim_core/fixed/trig.hpp"

namespace sinew::muscle {
namespace {

fx::ArenaCarver layout(const MuscleModel& model, void* base, size_t size, MuscleState* s) {
  fx::ArenaCarver c(base, size);
  const size_t m = model.muscles.size(), ring = model.ring_vertices;
  s->ring_cos = c.take<fx::Unit>(ring);
  s->ring_sin = c.take<fx::Unit>(ring);
  s->frames = c.take<SliceFrame>(m * kSlices);
  for (int a = 0; a < 3; ++a) s->vertex[a] = c.take<fx::Len>(m * kSlices * ring);
  s->length = c.take<fx::Len>(m);
  s->scale = c.take<fx::Unit>(m);
  s->last_points = c.take<fx::Vec3>(m * 5);
  s->computed = c.take<uint8_t>(m);
  s->primitives = c.take<PrimitiveFrame>(model.primitives.size());
  return c;
}

}  // namespace

size_t muscle_state_bytes(const MuscleModel& model) {
  MuscleState probe;
  return layout(model, nullptr, 0, &probe).needed();
}

LayerStatus muscle_init(const MuscleModel& model, void* memory, size_t bytes, MuscleState* out) {
  if (out == nullptr) return layer_fail(LayerError::kArena, "muscle state", -1, "", "null output");
  const uint32_t ring = model.ring_vertices;
  if (ring < 4 || ring > kMaxRingVertices || ring % 4 != 0)
    return layer_fail(LayerError::kBadValue, "muscle model", -1, "ring_vertices", "must be a multiple of 4 in [4, 64]",
                      ring, true);
  if (model.muscles.size() > kMaxMuscles || model.primitives.size() > kMaxPrimitives)
    return layer_fail(LayerError::kBadValue, "muscle model", -1, "muscles", "more records than the documented maxima");
  if (!fx::aligned8(memory))
    return layer_fail(LayerError::kArena, "muscle state", -1, "memory", "null or not 8-byte aligned");
  MuscleState s;
  const fx::ArenaCarver c = layout(model, memory, bytes, &s);
  if (c.failed())
    return layer_fail(LayerError::kArena, "muscle state", -1, "bytes", "smaller than muscle_state_bytes",
                      static_cast<int64_t>(bytes), true);
  s.ring_vertices = ring;
  for (uint32_t j = 0; j < ring; ++j) {
    // j / ring of a turn (floor(2^32 / ring) per step; exact when ring is a power of two).
    const fx::Angle a = static_cast<fx::Angle>((uint64_t{1} << 32) / ring * j);
    const fx::SinCos sc = fx::sin_cos(a);
    s.ring_cos[j] = sc.cos;
    s.ring_sin[j] = sc.sin;
  }
  *out = s;
  return {};
}

}  // namespace sinew::muscle
