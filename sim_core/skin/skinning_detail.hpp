// Internal to sim_core/skin: the scalar per-vertex specification shared by the
// scalar loop (skinning.cpp) and the vector kernels, which fall back to it for
// every vertex they do not handle themselves.
#pragma once

#include <cstdint>
#include <span>

#include "skinning.hpp"

namespace sinew::skin::detail {

// One LBS vertex v written at out[index]; adds clamped linear entries to *saturated.
void skin_linear_vertex(const rig::Rig& rig, std::span<const fx::Mat34> palette, uint32_t v, const SkinnedVertices& out,
                        uint32_t index, uint32_t* saturated);

// One DQS vertex v written at out[index].
void skin_dual_vertex(const rig::Rig& rig, std::span<const fx::DualQuat> dual, uint32_t v, const SkinnedVertices& out,
                      uint32_t index);

#if defined(__x86_64__)
// The AVX2 kernel (skinning_avx2.cpp): same contract and same output words as
// the scalar loop. Only call it when the CPU supports AVX2.
uint32_t skin_vertices_avx2(const rig::Rig& rig, std::span<const fx::Mat34> palette,
                            std::span<const fx::DualQuat> dual_palette, uint32_t first, uint32_t count,
                            const SkinnedVertices& out);
#endif

#if defined(__aarch64__)
// The NEON kernel (skinning_neon.cpp): same contract and same output words as
// the scalar loop. Advanced SIMD is part of every AArch64 CPU.
uint32_t skin_vertices_neon(const rig::Rig& rig, std::span<const fx::Mat34> palette,
                            std::span<const fx::DualQuat> dual_palette, uint32_t first, uint32_t count,
                            const SkinnedVertices& out);
#endif

}  // namespace sinew::skin::detail
