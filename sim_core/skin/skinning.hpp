// Skinning job: rest vertices + skinning palette -> deformed positions and
// normals, per vertex by linear blend skinning (LBS) or dual-quaternion
// skinning (DQS, Kavan et al. 2008), as the rig's per-vertex method says.
#pragma once

#include <cstdint>
#include <span>

#include "sim_core/fixed/dual_quat.hpp"
#include "sim_core/rig/rig.hpp"

namespace sinew::skin {

// Output arrays, SoA, one entry per vertex of the processed range.
struct SkinnedVertices {
  std::span<fx::Len> position[3];
  std::span<fx::Unit> normal[3];  // may be empty (then normals are skipped)
};

// Skins vertices [first, first + count). LBS blends the palette matrices with
// the Q2.30 weights (a convex combination: no overflow), then transforms once
// ("blend then transform"); blended linear entries are clamped to +-64.
// Normals use the blended linear part (rigid joints) and are renormalised.
// DQS blends dual quaternions on the hemisphere of the vertex's first
// influence (antipodal handling), normalises, then transforms.
// Returns the number of saturated (clamped) values.
uint32_t skin_vertices(const rig::Rig& rig, std::span<const fx::Mat34> palette,
                       std::span<const fx::DualQuat> dual_palette, uint32_t first, uint32_t count,
                       const SkinnedVertices& out);

// Kernels. kScalar is the specification (skinning.cpp, every target); kAvx2
// (x86-64 with AVX2, detected at run time, LBS and DQS), kAvx512 (x86-64
// with AVX-512 F, VL and CD, detected at run time, LBS and DQS) and kNeon (every aarch64
// build, LBS) write the same words and return the same saturation count for
// every input (docs/numerics.md). LBS and DQS vertices each have their own
// kernel.
enum class LbsKernel : uint8_t { kScalar = 0, kAvx2 = 1, kNeon = 2, kAvx512 = 3 };
enum class DqsKernel : uint8_t { kScalar = 0, kAvx2 = 1, kAvx512 = 2 };

// Whether this CPU runs the kernel (kScalar: always).
bool lbs_kernel_supported(LbsKernel kernel);
bool dqs_kernel_supported(DqsKernel kernel);
// The kernels skin_vertices uses on this CPU.
LbsKernel lbs_kernel_default();
DqsKernel dqs_kernel_default();
const char* lbs_kernel_name(LbsKernel kernel);
const char* dqs_kernel_name(DqsKernel kernel);

// skin_vertices with explicit kernels; an unsupported kernel runs kScalar.
uint32_t skin_vertices(LbsKernel lbs, DqsKernel dqs, const rig::Rig& rig, std::span<const fx::Mat34> palette,
                       std::span<const fx::DualQuat> dual_palette, uint32_t first, uint32_t count,
                       const SkinnedVertices& out);

// The LBS kernel given and the DQS kernel of the same kind (kScalar: the
// whole specification).
uint32_t skin_vertices(LbsKernel kernel, const rig::Rig& rig, std::span<const fx::Mat34> palette,
                       std::span<const fx::DualQuat> dual_palette, uint32_t first, uint32_t count,
                       const SkinnedVertices& out);

}  // namespace sinew::skin
