// Adversarial skinned vertices shared by the word-for-word kernel tests: the
// vertex half of a generated rig (positions, normals, influences, methods),
// which the LBS and DQS tests stress the same way. Each test builds its own
// palette, the part that differs between the two blends.
#pragma once

#include <cstdint>
#include <initializer_list>
#include <random>
#include <vector>

#include "sim_core/fixed/dual_quat.hpp"
#include "sim_core/fixed/mat34.hpp"
#include "sim_core/rig/rig.hpp"

namespace sinew_skin_test {

inline constexpr int32_t kWeightOne = int32_t{1} << 30;  // 1 in Q2.30

// How the vertices of a generated rig stress a kernel.
struct VertexStress {
  uint32_t k = 4;  // influences per vertex, 1..8
  uint32_t vertices = 200;
  int weight_mode = 0;    // 0 convex, 1 zeros and one-hots, 2 signed (sum |w| <= 2^31), 3 one extreme weight
  int position_mode = 0;  // 0 rig-sized, 1 full int32 and extremes
  int normal_mode = 0;    // 0 random, 1 zero and huge, 2 no normals
  uint8_t method = 0;     // rig::SkinMethod of most vertices
  uint8_t other_method = 0;
  bool mixed = false;                    // about a third of the vertices take other_method
  std::vector<int32_t> extreme_weights;  // weight_mode 3 picks its one weight from these
};

struct AdversarialRig {
  std::vector<int32_t> position[3], normal[3], weight;
  std::vector<uint16_t> joint;
  std::vector<uint8_t> method;
  std::vector<sinew::fx::Mat34> palette;
  std::vector<sinew::fx::DualQuat> dual;
  sinew::rig::Rig rig;
};

inline int32_t stress_pick(std::mt19937_64& rng, std::initializer_list<int32_t> values) {
  return values.begin()[rng() % values.size()];
}

inline int32_t stress_uniform(std::mt19937_64& rng, int64_t lo, int64_t hi) {
  return static_cast<int32_t>(std::uniform_int_distribution<int64_t>(lo, hi)(rng));
}

// Appends s.vertices vertices whose influences name joints below `palette`,
// then points r->rig at the arrays (call after the palette is built).
inline void add_stress_vertices(const VertexStress& s, uint32_t palette, bool any_dual, std::mt19937_64& rng,
                                AdversarialRig* r) {
  for (uint32_t v = 0; v < s.vertices; ++v) {
    for (int i = 0; i < 3; ++i) {
      r->position[i].push_back(s.position_mode == 0 ? stress_uniform(rng, -(1 << 22), 1 << 22)
                               : rng() % 2          ? stress_pick(rng, {INT32_MIN, INT32_MAX, INT32_MIN + 1, 0, -1})
                                                    : stress_uniform(rng, INT32_MIN, INT32_MAX));
      if (s.normal_mode == 0) r->normal[i].push_back(stress_uniform(rng, -(1 << 30), 1 << 30));
      if (s.normal_mode == 1)
        r->normal[i].push_back(rng() % 3 == 0 ? 0 : stress_pick(rng, {INT32_MIN, INT32_MAX, 0, 1, -1, 1 << 30}));
    }
    if (s.normal_mode == 1 && v % 5 == 0)
      for (int i = 0; i < 3; ++i) r->normal[i].back() = 0;  // zero normal
    r->method.push_back(s.mixed && rng() % 3 == 0 ? s.other_method : s.method);
    int64_t left = kWeightOne;
    const uint32_t hot = static_cast<uint32_t>(rng() % s.k);
    for (uint32_t k = 0; k < s.k; ++k) {
      r->joint.push_back(static_cast<uint16_t>(rng() % palette));
      int32_t w = 0;
      switch (s.weight_mode) {
        case 0:
          w = static_cast<int32_t>(k + 1 == s.k ? left : stress_uniform(rng, 0, left));
          left -= w;
          break;
        case 1:
          w = rng() % 4 == 0 ? 0 : (k == hot ? kWeightOne : 0);
          break;
        case 2:
          w = stress_uniform(rng, -(int64_t{1} << 31) / 8, (int64_t{1} << 31) / 8);
          break;
        default:
          w = k == hot ? s.extreme_weights[static_cast<size_t>(rng() % s.extreme_weights.size())] : 0;
          break;
      }
      r->weight.push_back(w);
    }
  }
  r->rig.influences_per_vertex = s.k;
  for (int i = 0; i < 3; ++i) {
    r->rig.position[i] = r->position[i];
    r->rig.normal[i] = r->normal[i];
  }
  r->rig.influence_palette = r->joint;
  r->rig.influence_weight = r->weight;
  r->rig.method = r->method;
  r->rig.any_dual_quaternion = any_dual;
}

}  // namespace sinew_skin_test
