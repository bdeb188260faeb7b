// Steps 1 and 2a of the bar-net step (barnet_step.hpp): every node's
// smooth-skinned position s (the blend of its bones' transforms, rounded
// once), and every free node's rest load turned by its blended bones and
// kept at its bind-pose magnitude. The scalar function is the
// specification; the AVX2 kernel (node_skinning_avx2.cpp, x86-64 only,
// chosen when the CPU reports AVX2) writes the same words and counts the
// same saturations for every input, and the kernel tests compare them word
// for word.
#pragma once

#include <cstdint>
#include <span>

#include "barnet_state.hpp"
#include "sim_core/fixed/scalar.hpp"

namespace sinew::barnet::detail {

// s of node n: sum_k w_k (S_jk rest), each transform rounded to Len, the
// blend rounded once (Q2.30 weights >= 0 summing to 2^30: the sum stays
// below 2^61).
fx::Vec3 skinned_position(const NodeRecord& n, std::span<const fx::Mat34> skin, fx::Saturation& sat);
// The blend of n's bones' linear parts applied to `direction` (Q2.30),
// before normalisation: sum_k w_k (M_jk direction), rounded once.
fx::Vec3 turned_direction(const NodeRecord& n, std::span<const fx::Mat34> skin, fx::Vec3 direction,
                          fx::Saturation& sat);

// Writes s of node i to node[c][i] for every node, and also to
// st->skinned[c][i] for a free one (the solve's starting point); writes
// st->load[c][i], the turned rest load (Q.36 force), for every free node.
// Reads st->skin (this step's skinning matrices). The model is validated
// (barnet_validate: every node's weights >= 0 and summing to 2^30) and every
// span was checked by the caller.
void skin_nodes(const BarnetModel& m, BarnetState* st, const std::span<fx::Len> (&node)[3], fx::Saturation& sat,
                VectorKernel kernel);

#if defined(__x86_64__)
// node_skinning_avx2.cpp; called only when the CPU reports AVX2.
void skin_nodes_avx2(const BarnetModel& m, BarnetState* st, const std::span<fx::Len> (&node)[3], fx::Saturation& sat);
#endif

}  // namespace sinew::barnet::detail
