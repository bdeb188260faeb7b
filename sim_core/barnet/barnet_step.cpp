#include "barnet_step.hpp"

#include "barnet_refactor.hpp"
#include "node_skinning.hpp"
#include "status_message.hpp"
#include "wide_sat.hpp"
#include "wrap.hpp"

namespace sinew::barnet {
namespace {

int32_t component(fx::Vec3 v, size_t c) { return c == 0 ? v.x : (c == 1 ? v.y : v.z); }

// Activation of a load: clamp((angle - lo) / (hi - lo), 0, 1) in Q2.30.
fx::Unit activation(int32_t angle, int32_t lo, int32_t hi) {
  const int64_t num = int64_t{angle} - lo, den = int64_t{hi} - lo;  // |num|, |den| < 2^32
  if (num == 0 || (num < 0) != (den < 0)) return 0;
  if ((num < 0 ? -num : num) >= (den < 0 ? -den : den)) return fx::kUnitOne;
  return static_cast<fx::Unit>(fx::div_round(num * fx::kUnitOne, den));  // |num| * 2^30 < 2^62
}

LayerStatus check_spans(const BarnetModel& m, const StepInputs& in, const StepOutputs& out) {
  if (in.bones.size() < m.joint_count)
    return fail(LayerError::kBadInput, "inputs.bones: fewer than joint_count transforms");
  if (in.joint_angles.size() < m.input_count)
    return fail(LayerError::kBadInput, "inputs.joint_angles: fewer than input_count angles");
  if (in.external.size() < m.external_count)
    return fail(LayerError::kBadInput, "inputs.external: fewer than external_count values");
  for (size_t c = 0; c < 3; ++c) {
    if (out.node[c].size() < m.nodes.size())
      return fail(LayerError::kBadInput, "outputs.node: shorter than the node count");
    if (out.skin[c].size() < m.wrap.size())
      return fail(LayerError::kBadInput, "outputs.skin: shorter than the wrap count");
  }
  return {};
}

}  // namespace

LayerStatus barnet_step(BarnetState* st, const StepInputs& in, const StepOutputs& out) {
  const BarnetModel& m = *st->model;
  LayerStatus s = check_spans(m, in, out);
  if (!s.ok()) return s;
  fx::Saturation sat;
  const uint32_t free = st->free_count;

  // Skinning matrices S_j = G_j x B_j^-1 (the rig's palette, per joint).
  for (uint32_t j = 0; j < m.joint_count; ++j) st->skin[j] = fx::mul(in.bones[j], m.inverse_bind[j]);

  // 1. Control mesh: every node's smooth-skinned position s, in out.node
  //    (the fixed nodes' x_f, eq. (4)'s input; the free nodes' are replaced
  //    by the solve below, which starts from their copy in st->skinned).
  // 2. The load p of eq. (4) on every free node, in Q.36 force: first its
  //    rest load (barnet_state.cpp), turned by the node's blended bones and
  //    kept at its bind-pose magnitude (node_skinning.hpp), ...
  detail::skin_nodes(m, st, out.node, sat, st->kernel);
  //    ... then the loads bound to joint angles or external inputs, carried
  //    by their bone (superposed; Q.24 x 2^12, below 1024 x 2^43 on a node).
  //    Loads of one input range come in runs (a bracket of a schedule):
  //    the activation of the record before is reused when its input and
  //    range are the same.
  fx::Unit t = 0;
  const LoadRecord* previous = nullptr;
  for (const LoadRecord& l : m.loads) {
    if (previous == nullptr || l.input != previous->input || l.angle_lo != previous->angle_lo ||
        l.angle_hi != previous->angle_hi) {
      const int32_t v = l.input < m.input_count ? in.joint_angles[l.input] : in.external[l.input - m.input_count];
      t = activation(v, l.angle_lo, l.angle_hi);
      previous = &l;
    }
    if (t == 0) continue;
    const fx::Vec3 force = t == fx::kUnitOne ? l.force : fx::scale(l.force, t);  // round(v 2^30 / 2^30) = v
    const fx::Mat34& bone = st->skin[l.joint];
    const fx::Vec3 f = fx::within(force, fx::kPlainVectorLimit) ? fx::transform_vector_plain(bone, force)
                                                                : fx::transform_vector(bone, force);
    for (size_t c = 0; c < 3; ++c) st->load[c][l.node] += int64_t{component(f, c)} * (int64_t{1} << 12);
  }

  // Force densities from inputs: D = C^T Q C re-assembled from this step's
  // q and re-factorised, the same work every step (barnet_refactor.hpp).
  // The pivots stay >= q_min / n because every scaled q stays >= q_min and
  // the net's connectivity was checked at init; the guard below cannot fire.
  if (!m.q_inputs.empty()) {
    scale_force_densities(m, in.external, st->q, sat);
    assemble_matrix(m.bars, st->q, st->factor);
    if (ldlt_factor(st->factor, st->work) < free) ++sat.events;
  }

  // 3. Eq. (4), per axis: x = D^-1 (p - D_f x_f), x_f the fixed nodes'
  //    skinned positions. Solved for the move d = x - s from the free nodes'
  //    skinned positions: D d = p - (D s + D_f x_f), whose right-hand side
  //    is formed exactly in Q.36 from the bars (row i of D s + D_f x_f is the
  //    sum over the bars at i of q (s_i - y_j), y_j the other end's skinned
  //    position), so the factor's relative error falls on the move alone.
  //    |p| <= 2^61 + 2^53 and the bar sum stays below 16 x 2^24 x 2^32 = 2^60.
  //    The three axes share one pass over the bars and one over the factor
  //    (work holds x, y and z of free node i at 3 i + c; out.node holds
  //    every node's skinned position until the solve's result replaces the
  //    free nodes').
  //    The spans' data are read into locals first: the stores to rhs
  //    could alias the span objects, which would make every bar reload them.
  int64_t* const rhs = st->work.data();
  for (uint32_t i = 0; i < free; ++i)
    for (size_t c = 0; c < 3; ++c) rhs[3 * i + c] = st->load[c][i];
  const fx::Len* const node[3] = {out.node[0].data(), out.node[1].data(), out.node[2].data()};
  const BarRecord* const bars = m.bars.data();
  const ForceDensity* const q = st->q.data();
  const size_t bar_count = m.bars.size();
  for (size_t b = 0; b < bar_count; ++b) {
    const uint32_t a = bars[b].a, other = bars[b].b;
    const int64_t qb = q[b];
    const int64_t pull[3] = {qb * (int64_t{node[0][a]} - node[0][other]), qb * (int64_t{node[1][a]} - node[1][other]),
                             qb * (int64_t{node[2][a]} - node[2][other])};
    if (a < free)
      for (size_t c = 0; c < 3; ++c) rhs[3 * a + c] -= pull[c];
    if (other < free)
      for (size_t c = 0; c < 3; ++c) rhs[3 * other + c] += pull[c];
  }
  for (uint32_t i = 0; i < 3 * free; ++i) rhs[i] = clamp_vector(rhs[i], sat);
  ldlt_solve_axes(st->factor, st->work.subspan(0, 3 * size_t{free}), sat, st->kernel);
  fx::Len max_disp = 0;
  for (uint32_t i = 0; i < free; ++i) {
    for (size_t c = 0; c < 3; ++c) {
      const int64_t d = fx::round_shift(rhs[3 * i + c], 20);  // Q.40 -> Len, |d| < 2^41
      const fx::Len x = fx::sat_i32(int64_t{st->skinned[c][i]} + d, sat);
      out.node[c][i] = x;
      const int64_t moved = int64_t{x} - st->skinned[c][i];
      const int64_t mag = moved < 0 ? -moved : moved;
      if (mag > max_disp) max_disp = fx::sat_i32(mag);
    }
  }

  // 4. Wrap: control-triangle frames (corners and unit normal), then every
  //    bound fine vertex (wrap.hpp).
  detail::make_triangle_frames(m, out.node, st->triangle, st->kernel);
  detail::wrap_vertices(m, st->triangle, st->wrap_bounded, out.skin, sat, st->kernel);

  st->stats.steps += 1;
  st->stats.saturated = sat.events;
  st->stats.max_displacement = max_disp;
  return {};
}

}  // namespace sinew::barnet
