#include "reaction.hpp"

#include "sim_core/fixed/rsqrt_fast.hpp"
#include "sim_core/fixed/wide.hpp"
#include "sim_core/layer/range_totals.hpp"
#include "sim_core/layer/selected.hpp"
#include "sim_core/muscle/primitive.hpp"
#include "sim_core/muscle/primitive_bound.hpp"
#include "sim_core/muscle/primitive_deform.hpp"
#include "sim_core/muscle/vec_ops.hpp"
#include "surface_normals.hpp"

namespace sinew::elastic_skin {
namespace {

// Primitives whose bounds a pass keeps (more are tested without the cull).
constexpr size_t kBoundedPrimitives = 16;

// Primitive i of the pass certainly leaves p alone.
bool far_from(const muscle::PrimitiveBound* bounds, size_t i, fx::Vec3 p) {
  return (i < kBoundedPrimitives) && muscle::beyond_bound(bounds[i], p);
}

// Some active primitive may move p (the passes' cheap first test).
bool within_reach(const muscle::MuscleState& muscles, const muscle::PrimitiveBound* bounds, fx::Vec3 p) {
  unsigned any = 0;
  for (size_t i = 0; i < muscles.primitives.size(); ++i)
    any |= static_cast<unsigned>(muscles.primitives[i].active != 0) & static_cast<unsigned>(!far_from(bounds, i, p));
  return any != 0;
}

void bound_primitives(const muscle::MuscleState& muscles, muscle::PrimitiveBound (&out)[kBoundedPrimitives]) {
  for (size_t i = 0; i < kBoundedPrimitives; ++i)
    out[i] = i < muscles.primitives.size() ? muscle::primitive_bound(muscles.primitives[i]) : muscle::PrimitiveBound{};
}

fx::Vec3 fat_point(const SkinModel& model, const SkinState& s, uint32_t v, fx::Vec3* normal) {
  const fx::Vec3 p{s.position[0][v], s.position[1][v], s.position[2][v]};
  if (s.fat_offsets != 0) {  // the step's offsets along the anchor normal (place_fat_points)
    *normal = {s.normal[0][v], s.normal[1][v], s.normal[2][v]};
    return fx::sub(p, {s.fat_offset[0][v], s.fat_offset[1][v], s.fat_offset[2][v]});
  }
  *normal = fat_direction(model, s, v);
  return fx::sub(p, muscle::along(*normal, fat_of(model, v)));
}

// fat_point's point alone, inlined into the passes' first test.
[[gnu::always_inline]] inline fx::Vec3 fat_point_only(const SkinModel& model, const SkinState& s, uint32_t v) {
  if (s.fat_offsets != 0)
    return {fx::sub_sat(s.position[0][v], s.fat_offset[0][v]), fx::sub_sat(s.position[1][v], s.fat_offset[1][v]),
            fx::sub_sat(s.position[2][v], s.fat_offset[2][v])};
  fx::Vec3 n{};
  return fat_point(model, s, v, &n);
}

}  // namespace

fx::Len fat_of(const SkinModel& model, uint32_t v) { return fx::add_sat(model.fat[v], model.solver.fat_thickness); }

void place_fat_points(const SkinModel& model, SkinState* s, const layer::Workers* workers) {
  s->fat_offsets = 0;
  if (surface_mode(model, *s)) return;  // the direction follows the relaxed skin, round by round
  const auto range = [&](uint32_t begin, uint32_t end) {
    for (uint32_t k = begin; k < end; ++k) {
      const uint32_t v = s->moving_vertex[k];
      const fx::Vec3 offset = muscle::along({s->normal[0][v], s->normal[1][v], s->normal[2][v]}, fat_of(model, v));
      s->fat_offset[0][v] = offset.x;
      s->fat_offset[1][v] = offset.y;
      s->fat_offset[2][v] = offset.z;
    }
    return 0u;
  };
  layer::run_ranges_summed(workers, s->moving_vertices, range);
  s->fat_offsets = 1;
}

uint32_t list_reaction_candidates(const SkinModel& model, const muscle::MuscleState& muscles, SkinState* s) {
  muscle::PrimitiveBound bounds[kBoundedPrimitives];
  bound_primitives(muscles, bounds);
  uint32_t count = 0;
  for (uint32_t v = 0; v < model.vertex_count; ++v) {
    fx::Vec3 n{};
    const fx::Vec3 p = fat_point(model, *s, v, &n);
    for (size_t i = 0; i < muscles.primitives.size(); ++i) {
      // The wide reach, not the box: the substep's sweeps move the listed
      // vertices only, and one just outside the box at listing could come
      // inside.
      if (muscles.primitives[i].active == 0 || (i < kBoundedPrimitives && muscle::beyond_reach(bounds[i], p))) continue;
      s->weight[count++] = v;
      break;
    }
  }
  return count;
}

uint32_t apply_sliding_reactions(const SkinModel& model, const muscle::MuscleState& muscles, uint32_t candidates,
                                 SkinState* s) {
  uint32_t moved = 0;
  const int steps = static_cast<int>(model.params.newton_steps);
  muscle::PrimitiveBound bounds[kBoundedPrimitives];
  bound_primitives(muscles, bounds);
  for (uint32_t k = 0; k < candidates; ++k) {
    const uint32_t v = static_cast<uint32_t>(s->weight[k]);
    fx::Vec3 n{};
    fx::Vec3 p = fat_point(model, *s, v, &n);
    bool any = false;
    for (size_t i = 0; i < muscles.primitives.size(); ++i) {
      const muscle::PrimitiveFrame& f = muscles.primitives[i];
      if (f.active == 0 || far_from(bounds, i, p)) continue;
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
      // affected, so the elastic surface may slide along"). Relative to the
      // layer beneath, which the bones carry as they carry the vertex's
      // anchor: a muscle moving out into the skin hands it its speed, and a
      // skin carried with a jumping bone keeps the carried speed.
      fx::Vec3 dir{};
      if (!fx::normalize_to_unit(d, &dir)) continue;
      const int64_t vd[3] = {dir.x, dir.y, dir.z};
      // (v - v_anchor) . dir; within a tick both are displacements per
      // substep (Q28.36, <= 2^50 each).
      int64_t along = 0;
      for (int c = 0; c < 3; ++c)
        along += fx::mul_shift_round(s->velocity[c][v] - s->anchor_step[c][v], vd[c], fx::kUnitFracBits);
      if (along >= 0) continue;
      for (int c = 0; c < 3; ++c) s->velocity[c][v] -= fx::mul_shift_round(along, vd[c], fx::kUnitFracBits);
    }
    if (!any) continue;
    for (int c = 0; c < 3; ++c) s->fine[c][v] = int64_t{s->position[c][v]} << 16;
    ++moved;
  }
  return moved;
}

uint32_t reaction_moves(const SkinModel& model, const muscle::MuscleState& muscles, uint32_t candidates, SkinState* s) {
  uint32_t inside = 0;
  const int steps = static_cast<int>(model.params.newton_steps);
  muscle::PrimitiveBound bounds[kBoundedPrimitives];
  bound_primitives(muscles, bounds);
  for (uint32_t k = 0; k < candidates; ++k) {
    const uint32_t v = static_cast<uint32_t>(s->weight[k]);
    fx::Vec3 n{};
    const fx::Vec3 start = fat_point(model, *s, v, &n);
    fx::Vec3 p = start, direction{0, 0, 0};
    for (size_t i = 0; i < muscles.primitives.size(); ++i) {
      const muscle::PrimitiveFrame& f = muscles.primitives[i];
      if (f.active == 0 || far_from(bounds, i, p)) continue;
      if (direction == fx::Vec3{0, 0, 0}) {
        // §6.11: the constraint gradient, of the first primitive the point
        // is inside, at the point (Q2.30 whatever the depth).
        const muscle::PrimitiveSample here = muscle::primitive_sample(f, p);
        if (here.inside) direction = here.normal == fx::Vec3{0, 0, 0} ? n : here.normal;
      }
      p = muscle::primitive_push_out(f, p, n, steps);
    }
    const fx::Vec3 d = fx::sub(p, start);
    const bool in = !(d == fx::Vec3{0, 0, 0}) && !(direction == fx::Vec3{0, 0, 0});
    s->reaction_normal[0][v] = in ? direction.x : 0;
    s->reaction_normal[1][v] = in ? direction.y : 0;
    s->reaction_normal[2][v] = in ? direction.z : 0;
    const uint64_t d2 = uint64_t(int64_t{d.x} * d.x) + uint64_t(int64_t{d.y} * d.y) + uint64_t(int64_t{d.z} * d.z);
    s->reaction_floor[v] = in ? int64_t{fx::isqrt_fast(d2)} * (int64_t{1} << 16) : 0;  // depth, Q28.36
    if (in) ++inside;
  }
  return inside;
}

uint32_t apply_reaction_constraints(const SkinModel& model, const muscle::MuscleState& muscles, fx::Unit gain,
                                    SkinState* s, const layer::Workers* workers) {
  const int steps = static_cast<int>(model.params.newton_steps);
  muscle::PrimitiveBound bounds[kBoundedPrimitives];
  bound_primitives(muscles, bounds);
  // Each vertex reads and moves only itself: the ranges run on any thread.
  // Most fat points are beyond every primitive's box: they are listed out
  // first, without a branch each (layer/selected.hpp).
  const uint32_t* const moving = s->moving_vertex.data();
  const auto near = [&](uint32_t k) { return within_reach(muscles, bounds, fat_point_only(model, *s, moving[k])); };
  const auto range = [&](uint32_t begin, uint32_t end) {
    uint32_t moved = 0;
    layer::visit_selected(begin, end, near, [&](uint32_t k) {
      const uint32_t v = moving[k];
      fx::Vec3 n{};
      const fx::Vec3 start = fat_point(model, *s, v, &n);
      fx::Vec3 p = start;
      for (size_t i = 0; i < muscles.primitives.size(); ++i) {
        const muscle::PrimitiveFrame& f = muscles.primitives[i];
        if (f.active == 0 || far_from(bounds, i, p)) continue;
        const fx::Vec3 out = muscle::primitive_push_out(f, p, n, steps);
        if (out == p) continue;
        // Partial correction between iterations, full one on the last.
        p = gain >= fx::kUnitOne ? out : fx::add(p, fx::scale(fx::sub(out, p), gain));
      }
      if (p == start) return;
      const fx::Vec3 d = fx::sub(p, start);
      s->position[0][v] = fx::add_sat(s->position[0][v], d.x);
      s->position[1][v] = fx::add_sat(s->position[1][v], d.y);
      s->position[2][v] = fx::add_sat(s->position[2][v], d.z);
      ++moved;
    });
    return moved;
  };
  return layer::run_ranges_summed(workers, s->moving_vertices, range);
}

namespace {

// count_inside_of over listed[first .. first + count) (vertex indices of
// either type), or the vertices first .. first + count with no list.
template <typename Index>
uint32_t count_inside_listed(const SkinModel& model, const muscle::MuscleState& muscles, fx::Unit tolerance,
                             const SkinState& s, const Index* listed, uint32_t count, uint32_t first) {
  uint32_t inside = 0;
  const int64_t limit = fx::kUnitOne - int64_t{tolerance};
  muscle::PrimitiveBound bounds[kBoundedPrimitives];
  bound_primitives(muscles, bounds);
  const auto vertex_of = [&](uint32_t k) {
    return listed != nullptr ? static_cast<uint32_t>(listed[first + k]) : first + k;
  };
  const auto near = [&](uint32_t k) { return within_reach(muscles, bounds, fat_point_only(model, s, vertex_of(k))); };
  layer::visit_selected(0, count, near, [&](uint32_t k) {
    fx::Vec3 n{};
    const fx::Vec3 p = fat_point(model, s, vertex_of(k), &n);
    for (size_t i = 0; i < muscles.primitives.size(); ++i) {
      const muscle::PrimitiveFrame& f = muscles.primitives[i];
      if (f.active == 0 || far_from(bounds, i, p)) continue;
      if (muscle::primitive_value(f, p) < limit) {
        ++inside;
        break;
      }
    }
  });
  return inside;
}

}  // namespace

uint32_t count_inside(const SkinModel& model, const muscle::MuscleState& muscles, fx::Unit tolerance,
                      const SkinState& s, const layer::Workers* workers) {
  const auto range = [&](uint32_t begin, uint32_t end) {
    return count_inside_listed(model, muscles, tolerance, s, s.moving_vertex.data(), end - begin, begin);
  };
  return layer::run_ranges_summed(workers, s.moving_vertices, range);
}

uint32_t count_inside_of(const SkinModel& model, const muscle::MuscleState& muscles, fx::Unit tolerance,
                         const SkinState& s, const int64_t* listed, uint32_t count, uint32_t first) {
  return count_inside_listed(model, muscles, tolerance, s, listed, count, first);
}

}  // namespace sinew::elastic_skin
