#include "surface_normals.hpp"

#include "sim_core/fixed/rsqrt_fast.hpp"
#include "sim_core/fixed/scalar.hpp"
#include "sim_core/fixed/wide.hpp"

namespace sinew::elastic_skin {
namespace {

constexpr int kEdgeShift = 2;  // Len differences (< 2^32) -> |e| <= 2^30

}  // namespace

bool surface_mode(const SkinModel& model, const SkinState& s) {
  return model.solver.fat_normal == static_cast<uint8_t>(FatNormal::kSurface) &&
         s.surface_normal[0].size() == model.vertex_count;
}

void estimate_surface_normals(const SkinModel& model, SkinState* s) {
  if (!surface_mode(model, *s)) return;
  const uint32_t n = model.vertex_count;
  for (int c = 0; c < 3; ++c)
    for (uint32_t v = 0; v < n; ++v) s->force[c][v] = 0;
  const size_t faces = model.triangles.size() / 3;
  for (size_t f = 0; f < faces; ++f) {
    const uint32_t ia = model.triangles[3 * f], ib = model.triangles[3 * f + 1], ic = model.triangles[3 * f + 2];
    int64_t e1[3], e2[3];
    for (int c = 0; c < 3; ++c) {
      const int64_t a = s->position[c][ia];
      e1[c] = (s->position[c][ib] - a) >> kEdgeShift;
      e2[c] = (s->position[c][ic] - a) >> kEdgeShift;
    }
    const int64_t cross[3] = {e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2],
                              e1[0] * e2[1] - e1[1] * e2[0]};
    for (int c = 0; c < 3; ++c)
      for (uint32_t at : {ia, ib, ic}) s->force[c][at] = fx::add_sat_i64(s->force[c][at], cross[c]);
  }
  for (uint32_t v = 0; v < n; ++v) {
    const int64_t sum[3] = {s->force[0][v], s->force[1][v], s->force[2][v]};
    uint64_t largest = 0;
    for (int64_t x : sum)
      if (fx::magnitude(x) > largest) largest = fx::magnitude(x);
    // Narrow to 30 significant bits (the direction is what is kept).
    int shift = 0;
    while ((largest >> shift) >= (uint64_t{1} << 30)) ++shift;
    const auto narrow = [&](int64_t x) { return fx::sat_i32(shift > 0 ? fx::round_shift(x, shift) : x); };
    fx::Vec3 unit{};
    fx::normalize_fast({narrow(sum[0]), narrow(sum[1]), narrow(sum[2])}, &unit);
    const int64_t side = int64_t{unit.x} * s->normal[0][v] + int64_t{unit.y} * s->normal[1][v] +
                         int64_t{unit.z} * s->normal[2][v];  // |each| <= 2^62 / 2: the sum fits
    if (side < 0) unit = {fx::neg_sat(unit.x), fx::neg_sat(unit.y), fx::neg_sat(unit.z)};
    s->surface_normal[0][v] = unit.x;
    s->surface_normal[1][v] = unit.y;
    s->surface_normal[2][v] = unit.z;
  }
}

fx::Vec3 fat_direction(const SkinModel& model, const SkinState& s, uint32_t v) {
  if (surface_mode(model, s)) {
    const fx::Vec3 m{s.surface_normal[0][v], s.surface_normal[1][v], s.surface_normal[2][v]};
    if (!(m == fx::Vec3{0, 0, 0})) return m;
  }
  return {s.normal[0][v], s.normal[1][v], s.normal[2][v]};
}

}  // namespace sinew::elastic_skin
