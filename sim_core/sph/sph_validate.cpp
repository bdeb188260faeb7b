#include "sim_core/rig/message.hpp"
#include "sph_model.hpp"

namespace sinew::sph {
namespace {

LayerStatus fail(LayerError e, const char* field, const char* what, int64_t value) {
  LayerStatus s;
  s.error = e;
  rig::MessageBuilder(s.message, sizeof s.message)
      .text("sph model: ")
      .text(field)
      .text(" ")
      .text(what)
      .text(" (got ")
      .number(value)
      .text(")");
  return s;
}

bool in(int64_t v, int64_t lo, int64_t hi) { return v >= lo && v <= hi; }

}  // namespace

// joint_count / vertex_count 0: no rig to check the indices against.
static LayerStatus check_model(const SphModel& m, uint32_t joint_count, uint32_t vertex_count) {
  const SphParams& p = m.params;
  const uint32_t n = m.particle_count();
  if (n == 0) return fail(LayerError::kBadCount, "particle count", "must be at least 1", 0);
  if (n > kMaxParticles) return fail(LayerError::kBadCount, "particle count", "exceeds kMaxParticles = 8192", n);
  for (int c = 0; c < 3; ++c)
    if (m.rest_local[c].size() != n || m.rest_model[c].size() != n)
      return fail(LayerError::kBadCount, "rest positions", "must have one entry per particle",
                  int64_t(m.rest_local[c].size()));
  if (p.h <= 0) return fail(LayerError::kBadValue, "h", "(kernel radius) must be > 0", p.h);
  if (!in(p.substeps, 1, kMaxSubsteps)) return fail(LayerError::kBadValue, "substeps", "must be in 1..16", p.substeps);
  if (!in(p.max_neighbours, 1, kMaxNeighbours))
    return fail(LayerError::kBadValue, "max_neighbours", "must be in 1..96", p.max_neighbours);
  if (!in(p.elastic_gain, 0, fx::kUnitOne - 1))
    return fail(LayerError::kBadValue, "elastic_gain", "must be in [0, 1) (Q2.30)", p.elastic_gain);
  if (!in(p.pressure_gain, 0, fx::kUnitOne - 1))
    return fail(LayerError::kBadValue, "pressure_gain", "must be in [0, 1) (Q2.30)", p.pressure_gain);
  if (!in(p.viscosity_gain, 0, fx::kUnitOne - 1))
    return fail(LayerError::kBadValue, "viscosity_gain", "must be in [0, 1) (Q2.30)", p.viscosity_gain);
  if (!in(p.tension_gain, 0, fx::kUnitOne - 1))
    return fail(LayerError::kBadValue, "tension_gain", "must be in [0, 1) (Q2.30)", p.tension_gain);
  if (!in(p.damping, 1, fx::kUnitOne))
    return fail(LayerError::kBadValue, "damping", "must be in (0, 1] (Q2.30)", p.damping);
  if (p.load_gain < 0) return fail(LayerError::kBadValue, "load_gain", "must be >= 0", p.load_gain);
  if (p.tau_f <= 0) return fail(LayerError::kBadValue, "tau_f", "(Tresca limit) must be > 0", p.tau_f);
  if (p.yield_count < 1) return fail(LayerError::kBadValue, "yield_count", "must be at least 1", p.yield_count);
  if (p.grid_radius <= 0 || p.grid_radius < p.h)
    return fail(LayerError::kBadValue, "grid_radius", "must be >= h", p.grid_radius);
  const int64_t dim = (2 * int64_t{p.grid_radius} + p.h - 1) / p.h;
  if (dim > kMaxGridDim)
    return fail(LayerError::kBadValue, "grid_radius", "over h gives more than 64 cells per axis", dim);
  const fx::Vec3 a = m.joint.axis;
  const int64_t a2 = fx::dot_wide(a, a) >> 30;  // Q30
  if (!in(a2, fx::kUnitOne - (fx::kUnitOne >> 10), fx::kUnitOne + (fx::kUnitOne >> 10)))
    return fail(LayerError::kBadValue, "joint.axis", "must be a unit vector (Q2.30 squared length)", a2);
  if (joint_count != 0) {
    if (m.joint.proximal_joint >= joint_count)
      return fail(LayerError::kBadIndex, "joint.proximal_joint", "is not a rig joint", m.joint.proximal_joint);
    if (m.joint.distal_joint >= joint_count)
      return fail(LayerError::kBadIndex, "joint.distal_joint", "is not a rig joint", m.joint.distal_joint);
  }
  if (m.joint.proximal_joint == m.joint.distal_joint)
    return fail(LayerError::kBadIndex, "joint.distal_joint", "must differ from proximal_joint", m.joint.distal_joint);
  uint32_t distal = 0;
  for (uint32_t i = 0; i < n; ++i) {
    if (m.bone[i] > 1) return fail(LayerError::kBadIndex, "bone", "must be 0 (proximal) or 1 (distal)", m.bone[i]);
    distal += m.bone[i];
  }
  if (distal == 0) return fail(LayerError::kBadCount, "bone", "no particle is bound to the distal bone", 0);
  if (p.yield_count > n) return fail(LayerError::kBadValue, "yield_count", "exceeds the particle count", p.yield_count);
  const uint32_t sv = m.skin_count();
  if (sv > kMaxSkinVertices) return fail(LayerError::kBadCount, "skin_vertex", "count exceeds 65536", sv);
  for (int c = 0; c < 3; ++c)
    if (m.skin_rest[c].size() != sv)
      return fail(LayerError::kBadCount, "skin_rest", "must have one entry per skin vertex",
                  int64_t(m.skin_rest[c].size()));
  if (vertex_count != 0)
    for (uint32_t v = 0; v < sv; ++v)
      if (m.skin_vertex[v] >= vertex_count)
        return fail(LayerError::kBadIndex, "skin_vertex", "is not a rig vertex", m.skin_vertex[v]);
  return {};
}

LayerStatus sph_validate(const SphModel& model, const rig::Rig& rig) {
  return check_model(model, rig.joint_count(), rig.vertex_count());
}

LayerStatus sph_validate_model(const SphModel& model) { return check_model(model, 0, 0); }

}  // namespace sinew::sph
