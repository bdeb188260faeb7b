#include "reaction.hpp"

#include "sim_core/fixed/wide.hpp"
#include "sim_core/muscle/primitive.hpp"
#include "sim_core/muscle/vec_ops.hpp"

namespace sinew::elastic_skin {
namespace {

fx::Vec3 fat_point(const SkinModel& model, const SkinState& s, uint32_t v, fx::Vec3* normal) {
  *normal = {s.normal[0][v], s.normal[1][v], s.normal[2][v]};
  const fx::Vec3 p{s.position[0][v], s.position[1][v], s.position[2][v]};
  return fx::sub(p, muscle::along(*normal, fat_of(model, v)));
}

}  // namespace

fx::Len fat_of(const SkinModel& model, uint32_t v) { return fx::add_sat(model.fat[v], model.solver.fat_thickness); }

uint32_t apply_sliding_reactions(const SkinModel& model, const muscle::MuscleState& muscles, SkinState* s) {
  uint32_t moved = 0;
  const int steps = static_cast<int>(model.params.newton_steps);
  for (uint32_t v = 0; v < model.vertex_count; ++v) {
    fx::Vec3 n{};
    fx::Vec3 p = fat_point(model, *s, v, &n);
    bool any = false;
    for (const muscle::PrimitiveFrame& f : muscles.primitives) {
      if (f.active == 0) continue;
      const fx::Vec3 out = muscle::primitive_push_out(f, p, n, steps);
      if (out == p) continue;
      const fx::Vec3 d = fx::sub(out, p);
      p = out;
      any = true;
      s->position[0][v] = fx::add_sat(s->position[0][v], d.x);
      s->position[1][v] = fx::add_sat(s->position[1][v], d.y);
      s->position[2][v] = fx::add_sat(s->position[2][v], d.z);
      // Velocity: drop the component into the primitive (against the move),
      // keep the tangential one (LEMAN §3: "forces perpendicular ... are not
      // affected, so the elastic surface may slide along").
      fx::Vec3 dir{};
      if (!fx::normalize_to_unit(d, &dir)) continue;
      const int64_t vd[3] = {dir.x, dir.y, dir.z};
      int64_t along = 0;  // v . dir, Q44.20: |v| < 2^47, |dir| <= 2^30
      for (int c = 0; c < 3; ++c) along += fx::mul_shift_round(s->velocity[c][v], vd[c], fx::kUnitFracBits);
      if (along >= 0) continue;
      for (int c = 0; c < 3; ++c) s->velocity[c][v] -= fx::mul_shift_round(along, vd[c], fx::kUnitFracBits);
    }
    if (!any) continue;
    for (int c = 0; c < 3; ++c) s->fine[c][v] = int64_t{s->position[c][v]} << 16;
    ++moved;
  }
  return moved;
}

uint32_t apply_reaction_constraints(const SkinModel& model, const muscle::MuscleState& muscles, fx::Unit gain,
                                    SkinState* s) {
  uint32_t moved = 0;
  const int steps = static_cast<int>(model.params.newton_steps);
  for (uint32_t v = 0; v < model.vertex_count; ++v) {
    fx::Vec3 n{};
    const fx::Vec3 start = fat_point(model, *s, v, &n);
    fx::Vec3 p = start;
    for (const muscle::PrimitiveFrame& f : muscles.primitives) {
      if (f.active == 0) continue;
      const fx::Vec3 out = muscle::primitive_push_out(f, p, n, steps);
      if (out == p) continue;
      // Partial correction between iterations, full one on the last.
      p = gain >= fx::kUnitOne ? out : fx::add(p, fx::scale(fx::sub(out, p), gain));
    }
    if (p == start) continue;
    const fx::Vec3 d = fx::sub(p, start);
    s->position[0][v] = fx::add_sat(s->position[0][v], d.x);
    s->position[1][v] = fx::add_sat(s->position[1][v], d.y);
    s->position[2][v] = fx::add_sat(s->position[2][v], d.z);
    ++moved;
  }
  return moved;
}

uint32_t count_inside(const SkinModel& model, const muscle::MuscleState& muscles, fx::Unit tolerance,
                      const SkinState& s) {
  uint32_t inside = 0;
  const int64_t limit = fx::kUnitOne - int64_t{tolerance};
  for (uint32_t v = 0; v < model.vertex_count; ++v) {
    fx::Vec3 n{};
    const fx::Vec3 p = fat_point(model, s, v, &n);
    for (const muscle::PrimitiveFrame& f : muscles.primitives) {
      if (f.active == 0) continue;
      if (muscle::primitive_sample(f, p).value < limit) {
        ++inside;
        break;
      }
    }
  }
  return inside;
}

}  // namespace sinew::elastic_skin
