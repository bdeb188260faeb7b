// Internal to sim_core/skin: the scalar per-vertex specification shared by the
// scalar loops (skinning.cpp) and the vector kernels, which fall back to it for
// every vertex they do not handle themselves.
#pragma once

#include <cstdint>
#include <cstring>
#include <span>

#include "sim_core/fixed/rsqrt_fast.hpp"
#include "skinning.hpp"

namespace sinew::skin::detail {

// Bound on the real components of a "near-unit" dual palette: 1.25 in Q2.30.
// Four products of such components sum below 4 * 1.25^2 * 2^60 < 2^63.
inline constexpr int64_t kDualRealLimit = (int64_t{1} << 30) + (int64_t{1} << 28);

// True if every real component of the palette lies in [-kDualRealLimit,
// kDualRealLimit] (every posed palette of unit quaternions does). Checked
// once per call, not per vertex.
bool dual_palette_near_unit(std::span<const fx::DualQuat> dual);

inline bool is_dual(const rig::Rig& rig, uint32_t v) {
  return rig.method[v] == static_cast<uint8_t>(rig::SkinMethod::kDualQuaternion);
}

// The first i in [i, end) whose vertex first + i is not DQS (end if none):
// the LBS passes skip runs of DQS vertices eight method bytes at a time.
inline uint32_t skip_dual_run(const rig::Rig& rig, uint32_t first, uint32_t i, uint32_t end) {
  const uint8_t* method = rig.method.data() + first;
  constexpr uint64_t kAllDual = 0x0101010101010101u * static_cast<uint8_t>(rig::SkinMethod::kDualQuaternion);
  for (; end - i >= 8; i += 8) {
    uint64_t eight;
    std::memcpy(&eight, method + i, sizeof(eight));
    if (eight != kAllDual) break;
  }
  while (i < end && is_dual(rig, first + i)) ++i;
  return i;
}

// The vector kernels are compiled per influence count K: runs
// kernel.template operator()<K>() for k in 1..8, fallback() for any other k.
template <typename Kernel, typename Fallback>
inline auto dispatch_influences(uint32_t k, Kernel&& kernel, Fallback&& fallback) {
  switch (k) {
    case 1:
      return kernel.template operator()<1>();
    case 2:
      return kernel.template operator()<2>();
    case 3:
      return kernel.template operator()<3>();
    case 4:
      return kernel.template operator()<4>();
    case 5:
      return kernel.template operator()<5>();
    case 6:
      return kernel.template operator()<6>();
    case 7:
      return kernel.template operator()<7>();
    case 8:
      return kernel.template operator()<8>();
    default:
      return fallback();
  }
}

// One LBS vertex v written at out[index]; adds clamped linear entries to *saturated.
void skin_linear_vertex(const rig::Rig& rig, std::span<const fx::Mat34> palette, uint32_t v, const SkinnedVertices& out,
                        uint32_t index, uint32_t* saturated);

// The rigid motion of a blended DQS vertex (skin_dual_vertex after the
// blend): b normalised by fx::normalize_fast, its rotation matrix and its
// translation t = 2 (w d_v - d_w r_v + r_v x d_v) as exact Q50 products
// (the factor 2 is applied by the caller, p' = R p + t + t).
struct DualMotion {
  fx::Rot3 rotation;
  int64_t t[3];
};
inline DualMotion dual_motion(fx::DualQuat b) {
  fx::normalize_fast(&b);
  DualMotion m;
  m.rotation = fx::rot3_of_unit(b.real);  // normalize_fast leaves it within a few LSB of unit
  const int64_t rw = b.real.w, rx = b.real.x, ry = b.real.y, rz = b.real.z;
  const int64_t dw = b.dual.w, dx = b.dual.x, dy = b.dual.y, dz = b.dual.z;
  // |t_c| <= |real| |dual| < (2^30 + 8) 2^32 (Cauchy-Schwarz; see normalize_fast): fits.
  m.t[0] = rw * dx - dw * rx + (ry * dz - rz * dy);
  m.t[1] = rw * dy - dw * ry + (rz * dx - rx * dz);
  m.t[2] = rw * dz - dw * rz + (rx * dy - ry * dx);
  return m;
}

// One DQS vertex v written at out[index]; near_unit is
// dual_palette_near_unit(dual) (the same words either way, only faster).
void skin_dual_vertex(const rig::Rig& rig, std::span<const fx::DualQuat> dual, uint32_t v, const SkinnedVertices& out,
                      uint32_t index, bool near_unit);

// Every DQS vertex of [first, first + count), by the scalar specification.
void skin_dual_scalar(const rig::Rig& rig, std::span<const fx::DualQuat> dual, uint32_t first, uint32_t count,
                      const SkinnedVertices& out);

#if defined(__x86_64__)
// The AVX2 kernels: the same contract and the same output words as the scalar
// loops. Only call them when the CPU supports AVX2.
// LBS (skinning_avx2.cpp): the LBS vertices of the range (DQS ones skipped
// when skip_dual); returns the saturation count.
uint32_t skin_linear_avx2(const rig::Rig& rig, std::span<const fx::Mat34> palette, bool skip_dual, uint32_t first,
                          uint32_t count, const SkinnedVertices& out);
// fx::normalize_fast of count unnormalised normals (SoA c[0..2]), written at
// out.normal[*][index[j]], four at a time (skinning_avx2.cpp).
void renormalise_normals_avx2(const int32_t* const c[3], const uint32_t* index, uint32_t count,
                              const SkinnedVertices& out);
// LBS with AVX-512 F, VL and CD (skinning_avx512.cpp): the same contract as
// skin_linear_avx2. Only call it when the CPU supports all three.
uint32_t skin_linear_avx512(const rig::Rig& rig, std::span<const fx::Mat34> palette, bool skip_dual, uint32_t first,
                            uint32_t count, const SkinnedVertices& out);
// DQS (skinning_dqs_avx2.cpp): every DQS vertex of the range.
void skin_dual_avx2(const rig::Rig& rig, std::span<const fx::DualQuat> dual, uint32_t first, uint32_t count,
                    const SkinnedVertices& out);
// DQS with AVX-512 F, VL and CD (skinning_dqs_avx512.cpp): the same contract
// as skin_dual_avx2. Only call it when the CPU supports all three.
void skin_dual_avx512(const rig::Rig& rig, std::span<const fx::DualQuat> dual, uint32_t first, uint32_t count,
                      const SkinnedVertices& out);
#endif

#if defined(__aarch64__)
// The NEON LBS kernel (skinning_neon.cpp): the same contract and the same
// output words as the scalar LBS loop (DQS vertices skipped when skip_dual);
// returns the saturation count. Advanced SIMD is part of every AArch64 CPU.
uint32_t skin_linear_neon(const rig::Rig& rig, std::span<const fx::Mat34> palette, bool skip_dual, uint32_t first,
                          uint32_t count, const SkinnedVertices& out);
#endif

}  // namespace sinew::skin::detail
