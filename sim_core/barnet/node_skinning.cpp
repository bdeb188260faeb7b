#include "node_skinning.hpp"

#include "sim_core/fixed/mat34.hpp"
#include "sim_core/fixed/rsqrt_fast.hpp"
#include "wide_sat.hpp"

namespace sinew::barnet::detail {
namespace {

// Convex combinations of Len or Q2.30 values with Q2.30 weights summing to
// 2^30: the accumulator never exceeds 2^61.
struct Blend {
  int64_t acc[3] = {0, 0, 0};
  void add(fx::Vec3 v, fx::Unit w) {
    acc[0] += int64_t{v.x} * w;
    acc[1] += int64_t{v.y} * w;
    acc[2] += int64_t{v.z} * w;
  }
  fx::Vec3 result(fx::Saturation& sat) const {
    return {fx::sat_i32(fx::round_shift(acc[0], 30), sat), fx::sat_i32(fx::round_shift(acc[1], 30), sat),
            fx::sat_i32(fx::round_shift(acc[2], 30), sat)};
  }
};

}  // namespace

fx::Vec3 skinned_position(const NodeRecord& n, std::span<const fx::Mat34> skin, fx::Saturation& sat) {
  Blend pos;
  if (fx::within(n.rest, fx::kPlainPointLimit)) {  // the same words without the overflow tests
    for (uint32_t k = 0; k < n.influence_count; ++k)
      pos.add(fx::transform_point_plain(skin[n.joint[k]], n.rest), n.weight[k]);
  } else {
    for (uint32_t k = 0; k < n.influence_count; ++k)
      pos.add(fx::transform_point(skin[n.joint[k]], n.rest), n.weight[k]);
  }
  return pos.result(sat);
}

fx::Vec3 turned_direction(const NodeRecord& n, std::span<const fx::Mat34> skin, fx::Vec3 direction,
                          fx::Saturation& sat) {
  Blend turned;
  if (fx::within(direction, fx::kPlainVectorLimit)) {  // a unit vector always is
    for (uint32_t k = 0; k < n.influence_count; ++k)
      turned.add(fx::transform_vector_plain(skin[n.joint[k]], direction), n.weight[k]);
  } else {
    for (uint32_t k = 0; k < n.influence_count; ++k)
      turned.add(fx::transform_vector(skin[n.joint[k]], direction), n.weight[k]);
  }
  return turned.result(sat);
}

void skin_nodes(const BarnetModel& m, BarnetState* st, const std::span<fx::Len> (&node)[3], fx::Saturation& sat,
                VectorKernel kernel) {
#if defined(__x86_64__)
  if (runs_avx2_loops(kernel) && vector_kernel_supported(VectorKernel::kAvx2)) return skin_nodes_avx2(m, st, node, sat);
#endif
  (void)kernel;
  const uint32_t free = st->free_count;
  // 1. Control mesh: smooth-skinned node positions. Fixed nodes keep them
  //    (x_f, eq. (4)'s input); free nodes keep them as the solve's starting
  //    point s.
  for (uint32_t i = 0; i < m.nodes.size(); ++i) {
    const fx::Vec3 p = skinned_position(m.nodes[i], st->skin, sat);
    node[0][i] = p.x, node[1][i] = p.y, node[2][i] = p.z;
    if (i < free) st->skinned[0][i] = p.x, st->skinned[1][i] = p.y, st->skinned[2][i] = p.z;
  }
  // 2a. The rest load turned by the node's blended bones, kept at its
  //     bind-pose magnitude (a bend turns the tissue's push, it does not
  //     weaken it).
  for (uint32_t i = 0; i < free; ++i) {
    fx::Vec3 unit{0, 0, 0};
    fx::normalize_fast(turned_direction(m.nodes[i], st->skin, st->rest_direction[i], sat),
                       &unit);  // opposite bones cancelling: no rest load
    st->load[0][i] = mul_shift_round_sat(st->rest_magnitude[i], unit.x, 30, sat);  // |.| <= 2^61
    st->load[1][i] = mul_shift_round_sat(st->rest_magnitude[i], unit.y, 30, sat);
    st->load[2][i] = mul_shift_round_sat(st->rest_magnitude[i], unit.z, 30, sat);
  }
}

}  // namespace sinew::barnet::detail
