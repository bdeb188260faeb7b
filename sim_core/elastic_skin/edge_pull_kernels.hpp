// Internal to sim_core/elastic_skin: the relaxation's first pass (each
// moving edge's pull, relaxation.cpp) by the scalar specification or by a
// vector kernel beside it. Every kernel writes the same words for every
// input; tests/sim_core/elastic_skin/edge_pull_kernel_test.cpp compares them.
#pragma once

#include <cstdint>

#include "skin_model.hpp"

namespace sinew::elastic_skin::detail {

// kAvx512: x86-64 with AVX-512 F, VL and CD, detected at run time.
enum class EdgePullKernel : uint8_t { kScalar, kAvx512 };

bool edge_pull_kernel_supported(EdgePullKernel kernel);
EdgePullKernel edge_pull_kernel_default();

// The pass's inputs and outputs as plain arrays. For each listed edge e:
// stiffness[e] the spring's effective stiffness (0 when it pulls with
// nothing) and pull[c][e] its pull on end a (edge_pull of relaxation.hpp).
struct EdgePullJob {
  const SkinParams* params;
  const Edge* edges;
  const fx::Len* position[3];
  const uint32_t* moving;  // edge indices, each at most once
  int32_t* stiffness;
  fx::Len* pull[3];
};

// Edge moving[i] by the scalar specification.
void pull_edge_scalar(const EdgePullJob& job, uint32_t i);

// Edges moving[begin..end) by `kernel` (an unsupported one runs kScalar).
void pull_edges_with(EdgePullKernel kernel, const EdgePullJob& job, uint32_t begin, uint32_t end);

#if defined(__x86_64__)
// Groups of eight of moving[begin..end); returns the first index it left
// (the scalar specification takes the rest). Only call it when the CPU has
// AVX-512 F, VL and CD.
uint32_t pull_edges_avx512(const EdgePullJob& job, uint32_t begin, uint32_t end);
#endif

}  // namespace sinew::elastic_skin::detail
