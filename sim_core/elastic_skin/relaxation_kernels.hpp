// Internal to sim_core/elastic_skin: two of the relaxation's passes
// (relaxation.cpp: each moving edge's pull, and each moving vertex's
// collision with its anchor sphere) by the scalar specification or by a
// vector kernel beside it. Every kernel writes the same words for every
// input; tests/sim_core/elastic_skin/relaxation_kernel_test.cpp compares them.
#pragma once

#include <cstdint>

#include "skin_model.hpp"

namespace sinew::elastic_skin::detail {

// kAvx512: x86-64 with AVX-512 F, VL and CD, detected at run time.
enum class RelaxationKernel : uint8_t { kScalar, kAvx512 };

bool relaxation_kernel_supported(RelaxationKernel kernel);
RelaxationKernel relaxation_kernel_default();

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

// The rest of the specification for a compressed edge e (ratio < 0) whose
// w = sub_sat(x_b, x_a), |w|^2 = n2 > 0 and ratio = 1 - rest / |w| (Q2.30,
// edge_spring's) a kernel has formed: its push-back stiffness and pull.
void pull_compressed_edge(const EdgePullJob& job, uint32_t e, const int64_t w[3], int64_t ratio, uint64_t n2);

// Edges moving[begin..end) by `kernel` (an unsupported one runs kScalar).
void pull_edges_with(RelaxationKernel kernel, const EdgePullJob& job, uint32_t begin, uint32_t end);

// The collision pass's inputs and outputs: each listed vertex v inside the
// sphere of radius `radius` about centre[.][v] is moved to its surface (to
// anchor[.][v] from the centre itself).
struct SphereJob {
  fx::Len* position[3];
  const fx::Len* centre[3];
  const fx::Len* anchor[3];
  const uint32_t* moving;  // vertex indices, each at most once
  fx::Len radius;          // > 0
};

// Vertex moving[i] by the scalar specification; 1 if it moved, else 0.
uint32_t collide_vertex_scalar(const SphereJob& job, uint32_t i);

// Vertices moving[begin..end) by `kernel` (an unsupported one runs
// kScalar); returns the number moved.
uint32_t collide_with_spheres_with(RelaxationKernel kernel, const SphereJob& job, uint32_t begin, uint32_t end);

#if defined(__x86_64__)
// Groups of eight of moving[begin..end), adding the vertices moved to
// *moved; returns the first index it left. Only call it when the CPU has
// AVX-512 F, VL and CD.
uint32_t collide_with_spheres_avx512(const SphereJob& job, uint32_t begin, uint32_t end, uint32_t* moved);

// Groups of eight of moving[begin..end); returns the first index it left
// (the scalar specification takes the rest). Only call it when the CPU has
// AVX-512 F, VL and CD.
uint32_t pull_edges_avx512(const EdgePullJob& job, uint32_t begin, uint32_t end);
#endif

}  // namespace sinew::elastic_skin::detail
