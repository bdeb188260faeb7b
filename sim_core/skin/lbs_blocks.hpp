// Internal to sim_core/skin: the vertex loop every vector LBS kernel shares.
// Include it inside the kernel's ISA region (isa_region.hpp), after the
// kernel's own includes: the loop is then compiled for the kernel's extension
// and inlines the kernel's per-vertex function; internal linkage keeps each
// kernel's copy its own.
#pragma once

#include <cstdint>

#include "skinning_detail.hpp"

namespace sinew::skin::detail {
namespace {

// Unnormalised normals of the fast-path vertices of one block, SoA: the
// kernel renormalises them after the block, so that the renormalisations of
// many vertices overlap.
inline constexpr uint32_t kLbsBlock = 64;
struct PendingNormals {
  int32_t c[3][kLbsBlock];
  uint32_t index[kLbsBlock];
  uint32_t count = 0;
};

// True if the LBS pass leaves vertex v to the DQS pass.
template <typename Job>
inline bool lbs_skips(const Job& job, uint32_t v) {
  return job.skip_dual && is_dual(*job.rig, v);
}

// Vertices [first, first + count) in blocks of kLbsBlock: runs of DQS
// vertices skipped when the job says so; each LBS vertex through
// Vertex(job, v, index, &pending), which returns false when the vertex might
// clamp (then the scalar specification writes it and counts the clamp); the
// block's pending normals through Finish(out, &pending) at its end.
template <auto Vertex, auto Finish, typename Job>
inline uint32_t run_lbs_blocks(const Job& job, uint32_t first, uint32_t count) {
  const rig::Rig& rig = *job.rig;
  uint32_t saturated = 0;
  PendingNormals pending;
  for (uint32_t block = 0; block < count;) {
    const uint32_t end = block + (count - block < kLbsBlock ? count - block : kLbsBlock);  // <= count: no wrap
    for (uint32_t i = block; i < end;) {
      const uint32_t v = first + i;
      if (lbs_skips(job, v)) {
        i = skip_dual_run(rig, first, i, end);
        continue;
      }
      if (!Vertex(job, v, i, &pending)) skin_linear_vertex(rig, job.palette, v, *job.out, i, &saturated);
      ++i;
    }
    Finish(*job.out, &pending);
    block = end;
  }
  return saturated;
}

// The scalar loop of skinning.cpp, for inputs no vector path takes (K outside
// 1..8, a palette larger than a kernel's widened buffer).
template <typename Job>
inline uint32_t run_lbs_scalar(const Job& job, uint32_t first, uint32_t count) {
  uint32_t saturated = 0;
  for (uint32_t i = 0; i < count; ++i) {
    const uint32_t v = first + i;
    if (!lbs_skips(job, v)) skin_linear_vertex(*job.rig, job.palette, v, *job.out, i, &saturated);
  }
  return saturated;
}

}  // namespace
}  // namespace sinew::skin::detail
