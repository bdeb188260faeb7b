// AVX2 kernel of the bar-net's node skinning (node_skinning.hpp), with the
// same output words and saturation count as the scalar specification
// (node_skinning.cpp) for every input. Compiled for AVX2 (isa_region.hpp),
// on x86-64 only; called only when the CPU reports AVX2.
//   - Each joint's skinning matrix is laid out once per step as columns in
//     int64 lanes (SkinColumns), so a transform is three vpmuldq products
//     plus the translation, the rows x, y and z side by side: the plain
//     int64 sums of transform_point_plain / transform_vector_plain, exact
//     under the same input bounds (a node outside them takes the
//     specification's path).
//   - Free nodes go four at a time: position and turned direction share one
//     pass over the influences, and the four turned directions are
//     normalised together by fx::avx2::normalize_fast_x4
//     (fx::normalize_fast's words), overlapping its chains of dependent
//     products.
//   - Each blend is rounded in its lanes: its convex weights keep it within
//     int32 (blend_result).
#include <immintrin.h>

#include <cstring>

#include "node_skinning.hpp"
#include "sim_core/fixed/avx2_lanes.hpp"
#include "sim_core/fixed/isa_region.hpp"
#include "sim_core/fixed/mat34.hpp"
#include "wide_sat.hpp"

SINEW_ISA_BEGIN("avx2")

namespace sinew::barnet::detail {
namespace {

constexpr uint32_t kLanes = 4;

inline __m256i mul(__m256i a, __m256i b) { return _mm256_mul_epi32(a, b); }
inline __m256i add(__m256i a, __m256i b) { return _mm256_add_epi64(a, b); }
inline __m256i load(const int64_t (&lanes)[4]) {
  __m256i x;
  std::memcpy(&x, lanes, sizeof(x));
  return x;
}

// A vector's components broadcast for vpmuldq, which reads the low 32 bits
// of each lane.
struct Broadcast {
  __m256i x, y, z;
  explicit Broadcast(fx::Vec3 v) : x(_mm256_set1_epi32(v.x)), y(_mm256_set1_epi32(v.y)), z(_mm256_set1_epi32(v.z)) {}
};

// M v as int64 rows x, y, z in lanes 0..2 (lane 3 zero): each product
// below 2^62 under the plain bounds, the sum exact.
inline __m256i linear_rows(const SkinColumns& s, const Broadcast& v) {
  return add(add(mul(load(s.column[0]), v.x), mul(load(s.column[1]), v.y)), mul(load(s.column[2]), v.z));
}

// sat_i32(round_shift(row, 24)) per lane: the plain transforms' rounding.
inline __m256i to_len(__m256i rows) {
  return fx::avx2::sat_i32_epi64(fx::avx2::round_shift_epi64<fx::kLinFracBits>(rows));
}

// The blend's rounding, sat_i32(round_shift(acc, 30), sat) per component,
// without the saturation: with weights >= 0 summing to 2^30 (barnet_validate)
// acc / 2^30 is a convex combination of int32 values, so its rounding lies
// within int32 and the specification's saturation never acts.
inline fx::Vec3 blend_result(__m256i acc) {
  int64_t a[kLanes];
  fx::avx2::lanes(fx::avx2::round_shift_epi64<30>(acc), a);
  return {static_cast<int32_t>(a[0]), static_cast<int32_t>(a[1]), static_cast<int32_t>(a[2])};
}

void lay_out_columns(std::span<const fx::Mat34> skin, std::span<SkinColumns> columns) {
  for (size_t j = 0; j < skin.size(); ++j) {
    const fx::Mat34& a = skin[j];
    SkinColumns& s = columns[j];
    for (int c = 0; c < 3; ++c)
      for (int r = 0; r < 3; ++r) s.column[c][r] = a.m[r][c];
    for (int r = 0; r < 3; ++r) s.translation[r] = int64_t{a.t[r]} * (int64_t{1} << fx::kLinFracBits);
    for (int c = 0; c < 3; ++c) s.column[c][3] = 0;
    s.translation[3] = 0;
  }
}

inline void store_position(const std::span<fx::Len> (&node)[3], uint32_t i, fx::Vec3 p) {
  node[0][i] = p.x, node[1][i] = p.y, node[2][i] = p.z;
}

}  // namespace

void skin_nodes_avx2(const BarnetModel& m, BarnetState* st, const std::span<fx::Len> (&node)[3], fx::Saturation& sat) {
  const std::span<const SkinColumns> columns = st->skin_columns;
  lay_out_columns(st->skin, st->skin_columns);
  const uint32_t free = st->free_count;

  // Free nodes, four per group (a last group of fewer repeats its last
  // node's direction in the spare lanes and stores only the real ones).
  for (uint32_t first = 0; first < free; first += kLanes) {
    const uint32_t count = free - first < kLanes ? free - first : kLanes;
    alignas(32) int64_t turned[3][kLanes];
    for (uint32_t l = 0; l < count; ++l) {
      const uint32_t i = first + l;
      const NodeRecord& n = m.nodes[i];
      const fx::Vec3 direction = st->rest_direction[i];
      fx::Vec3 p, d;
      if (fx::within(n.rest, fx::kPlainPointLimit) && fx::within(direction, fx::kPlainVectorLimit)) {
        const Broadcast rest(n.rest), dir(direction);
        __m256i pos = _mm256_setzero_si256(), turn = _mm256_setzero_si256();
        for (uint32_t k = 0; k < n.influence_count; ++k) {
          const SkinColumns& s = columns[n.joint[k]];
          const __m256i w = _mm256_set1_epi32(n.weight[k]);
          pos = add(pos, mul(to_len(add(linear_rows(s, rest), load(s.translation))), w));
          turn = add(turn, mul(to_len(linear_rows(s, dir)), w));
        }
        p = blend_result(pos);
        d = blend_result(turn);
      } else {
        p = skinned_position(n, st->skin, sat);
        d = turned_direction(n, st->skin, direction, sat);
      }
      store_position(node, i, p);
      st->skinned[0][i] = p.x, st->skinned[1][i] = p.y, st->skinned[2][i] = p.z;
      turned[0][l] = d.x, turned[1][l] = d.y, turned[2][l] = d.z;
    }
    for (uint32_t l = count; l < kLanes; ++l)
      for (int c = 0; c < 3; ++c) turned[c][l] = turned[c][count - 1];
    __m256i unit[3];
    fx::avx2::normalize_fast_x4(load(turned[0]), load(turned[1]), load(turned[2]), unit);
    int64_t u[3][kLanes];
    for (int c = 0; c < 3; ++c) fx::avx2::lanes(unit[c], u[c]);
    for (uint32_t l = 0; l < count; ++l) {
      const uint32_t i = first + l;
      for (int c = 0; c < 3; ++c) st->load[c][i] = mul_shift_round_sat(st->rest_magnitude[i], u[c][l], 30, sat);
    }
  }

  // Fixed nodes: the position alone.
  for (uint32_t i = free; i < m.nodes.size(); ++i) {
    const NodeRecord& n = m.nodes[i];
    if (!fx::within(n.rest, fx::kPlainPointLimit)) {
      store_position(node, i, skinned_position(n, st->skin, sat));
      continue;
    }
    const Broadcast rest(n.rest);
    __m256i pos = _mm256_setzero_si256();
    for (uint32_t k = 0; k < n.influence_count; ++k) {
      const SkinColumns& s = columns[n.joint[k]];
      pos = add(pos, mul(to_len(add(linear_rows(s, rest), load(s.translation))), _mm256_set1_epi32(n.weight[k])));
    }
    store_position(node, i, blend_result(pos));
  }
}

}  // namespace sinew::barnet::detail

SINEW_ISA_END
