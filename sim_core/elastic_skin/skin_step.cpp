#include "skin_step.hpp"

#include "reaction.hpp"
#include "relaxation.hpp"
#include "sim_core/fixed/rsqrt_fast.hpp"
#include "sim_core/fixed/sqrt.hpp"
#include "sim_core/fixed/wide.hpp"
#include "sim_core/layer/range_totals.hpp"
#include "sim_core/muscle/vec_ops.hpp"
#include "skin_dynamic.hpp"
#include "skin_validate.hpp"
#include "surface_normals.hpp"
#include "virtual_anchors.hpp"

namespace sinew::elastic_skin {
namespace {

// Penetration the final check tolerates: 2^-10 on the inside/outside function.
constexpr fx::Unit kInsideTolerance = fx::kUnitOne >> 10;

// Largest move of a vertex since the start of the iteration.
fx::Len largest_move(const SkinState& s, const layer::Workers* workers) {
  const auto range = [&](uint32_t begin, uint32_t end) {
    uint64_t worst = 0;  // squared: one root per range
    for (uint32_t i = begin; i < end; ++i) {
      const uint32_t v = s.moving_vertex[i];
      const uint64_t dx = fx::magnitude(int64_t{s.position[0][v]} - s.previous[0][v]);
      const uint64_t dy = fx::magnitude(int64_t{s.position[1][v]} - s.previous[1][v]);
      const uint64_t dz = fx::magnitude(int64_t{s.position[2][v]} - s.previous[2][v]);
      // Each difference < 2^32; clamp the sum of squares instead of wrapping.
      const uint64_t lim = uint64_t{1} << 62;
      const uint64_t d2 =
          (dx >= lim >> 31 || dy >= lim >> 31 || dz >= lim >> 31) ? UINT64_MAX : dx * dx + dy * dy + dz * dz;
      if (d2 > worst) worst = d2;
    }
    // floor(sqrt) is monotonic: the largest root is the root of the largest square.
    return static_cast<uint32_t>(fx::sat_i32(int64_t{fx::isqrt_fast(worst)}));
  };
  return static_cast<fx::Len>(layer::run_ranges_max(workers, s.moving_vertices, range));
}

// The last step's offset of a vertex from its anchor, turned with the
// anchor's normal (old -> fresh, both Q2.30 units) by the smallest rotation
// that takes one to the other (Rodrigues, k = old x fresh, c = old . fresh):
//   R v = c v + k x v + (k . v) k / (1 + c).
// Within 2^-10 of a half turn the axis is undefined: the vertex starts
// cold, on its anchor (offset 0).
fx::Vec3 carried_offset(fx::Vec3 offset, fx::Vec3 old_normal, fx::Vec3 fresh_normal) {
  const int64_t c = muscle::component(old_normal, fresh_normal);  // Q2.30
  const int64_t one_plus_c = fx::kUnitOne + c;
  if (one_plus_c < (fx::kUnitOne >> 10)) return {0, 0, 0};
  const fx::Vec3 k = muscle::cross_unit(old_normal, fresh_normal);  // |k| <= 1, Q2.30
  const fx::Vec3 kxv = fx::cross(k, offset, fx::kUnitFracBits);     // Len
  const int64_t kv = muscle::component(offset, k);                  // Len
  const int64_t o[3] = {offset.x, offset.y, offset.z}, kk[3] = {k.x, k.y, k.z}, cr[3] = {kxv.x, kxv.y, kxv.z};
  int32_t out[3];
  for (int a = 0; a < 3; ++a) {
    // (k . v) k_a / (1 + c): |k . v| < 2^33, |k_a| <= 2^30: the product fits.
    const int64_t axial = fx::div_round(kv * kk[a], one_plus_c);
    out[a] = fx::sat_i32(fx::round_shift(c * o[a], fx::kUnitFracBits) + cr[a] + axial);
  }
  return {out[0], out[1], out[2]};
}

LayerStatus bad_input(const char* field, const char* problem) {
  return muscle::layer_fail(LayerError::kBadInput, "skin step", -1, field, problem);
}

}  // namespace

LayerStatus skin_step(const SkinModel& model, const muscle::MuscleModel& muscles, const muscle::MuscleState& mstate,
                      std::span<const fx::Mat34> bones, SkinState* state) {
  return skin_step(model, muscles, mstate, bones, SkinTick{}, state);
}

LayerStatus skin_step(const SkinModel& model, const muscle::MuscleModel& muscles, const muscle::MuscleState& mstate,
                      std::span<const fx::Mat34> bones, const SkinTick& tick, SkinState* state) {
  if (state == nullptr) return bad_input("state", "null");
  if (bones.size() < model.joint_count) return bad_input("bones", "fewer transforms than the model's joints");
  if (state->vertex_count != model.vertex_count || state->weight.size() != model.vertex_count)
    return bad_input("state", "not initialised for this skin model");
  if (mstate.ring_vertices != muscles.ring_vertices ||
      mstate.frames.size() != muscles.muscles.size() * muscle::kSlices ||
      mstate.primitives.size() != muscles.primitives.size())
    return bad_input("muscle state", "not initialised for this muscle model");
  const LayerStatus checked = skin_check_indices(model, muscles, static_cast<uint32_t>(bones.size()));
  if (!checked.ok()) return checked;

  if (model.solver.mode == static_cast<uint8_t>(SkinMode::kDynamic))
    return skin_dynamic_step(model, muscles, mstate, bones, tick, state);

  SkinState& s = *state;
  SkinStats fresh;
  fresh.steps = s.stats.steps;
  s.stats = fresh;
  const bool warm = model.params.warm_start != 0 && s.started != 0;
  const layer::Workers* workers = tick.workers;
  // Each vertex reads and writes only its own entries: the ranges run on any thread.
  const auto anchors = [&](uint32_t begin, uint32_t end) {
    for (uint32_t k = begin; k < end; ++k) {
      const uint32_t v = s.mapped_vertex[k];
      const AnchorPoint a = map_anchor(model.anchors[v], bones, mstate);
      const fx::Len p[3] = {a.position.x, a.position.y, a.position.z};
      const fx::Unit nrm[3] = {a.normal.x, a.normal.y, a.normal.z};
      // Warm start (LEMAN §3): the last skin carried with its anchor, its
      // offset turned as the anchor's normal turned. The last skin left where
      // it was would trail every bone move by more than a few relaxations
      // make up (the skin ballooned off a fast-moving limb).
      fx::Vec3 offset{0, 0, 0};
      if (warm) {
        const fx::Vec3 last{fx::sat_i32(int64_t{s.position[0][v]} - s.anchor[0][v]),
                            fx::sat_i32(int64_t{s.position[1][v]} - s.anchor[1][v]),
                            fx::sat_i32(int64_t{s.position[2][v]} - s.anchor[2][v])};
        offset = carried_offset(last, {s.normal[0][v], s.normal[1][v], s.normal[2][v]}, a.normal);
      }
      const int32_t off[3] = {offset.x, offset.y, offset.z};
      for (int c = 0; c < 3; ++c) {
        s.position[c][v] = fx::sat_i32(int64_t{p[c]} + off[c]);
        s.anchor[c][v] = p[c];
        s.normal[c][v] = nrm[c];
      }
    }
    return 0u;
  };
  layer::run_ranges_summed(workers, s.mapped_vertices, anchors);
  place_anchor_spheres(model, &s, workers);  // the anchors hold for every round of the step
  place_fat_points(model, &s, workers);
  // §5.2: relax until the largest move falls below the tolerance or the
  // iteration count runs out; the last iteration run removes all remaining
  // penetration.
  const uint32_t iterations = model.params.iterations;
  const fx::Len tolerance = model.solver.tolerance;
  uint32_t run = 0;
  for (uint32_t i = 0; i < iterations; ++i) {
    for (int c = 0; c < 3; ++c)
      for (uint32_t k = 0; k < s.moving_vertices; ++k)
        s.previous[c][s.moving_vertex[k]] = s.position[c][s.moving_vertex[k]];
    relax_once(model, mstate, &s, workers);
    s.stats.collisions += collide_with_anchor_spheres(model, &s, workers);
    const bool last = i + 1 == iterations;
    const fx::Unit gain = last ? fx::kUnitOne : model.params.reaction_gain;
    estimate_surface_normals(model, &s);  // kSurface only: the fat along the relaxed skin's normal (§5.6)
    s.stats.reactions += apply_reaction_constraints(model, mstate, gain, &s, workers);
    s.max_relax[i] = largest_move(s, workers);
    run = i + 1;
    if (!last && tolerance > 0 && s.max_relax[i] < tolerance) {
      if (gain < fx::kUnitOne)
        s.stats.reactions += apply_reaction_constraints(model, mstate, fx::kUnitOne, &s, workers);
      s.stats.converged = 1;
      break;
    }
  }
  s.stats.iterations = run;
  s.stats.max_relax_first = s.max_relax[0];
  s.stats.max_relax_last = s.max_relax[run - 1];
  s.stats.residual = s.stats.max_relax_last;
  // Against the normals the last reaction pass used (re-estimating them from
  // the pushed skin would tilt some fat points back in by the push's turn).
  s.stats.inside_after = count_inside(model, mstate, kInsideTolerance, s, workers);
  s.started = 1;
  ++s.stats.steps;
  return {};
}

}  // namespace sinew::elastic_skin
