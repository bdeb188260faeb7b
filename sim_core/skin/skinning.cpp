#include "skinning.hpp"

#include "sim_core/fixed/rsqrt_fast.hpp"
#include "skinning_detail.hpp"

namespace sinew::skin {
namespace {

constexpr int64_t kLinearLimit = int64_t{1} << 30;  // +-64 in Q8.24

// R v for |R| <= 1 (+ rounding) and any int32 v: three products < 2^62 each.
inline void rotate_into(const fx::Rot3& r, const int64_t v[3], int64_t out[3]) {
  for (int i = 0; i < 3; ++i) out[i] = r.m[i][0] * v[0] + r.m[i][1] * v[1] + r.m[i][2] * v[2];
}

struct Blend {
  int64_t m[9];
  int64_t t[3];
};

}  // namespace

void detail::skin_linear_vertex(const rig::Rig& rig, std::span<const fx::Mat34> palette, uint32_t v,
                                const SkinnedVertices& out, uint32_t index, uint32_t* saturated) {
  const uint32_t k_count = rig.influences_per_vertex;
  const uint16_t* joints = rig.influence_palette.data() + size_t{v} * k_count;
  const fx::Unit* weights = rig.influence_weight.data() + size_t{v} * k_count;
  Blend b{};
  for (uint32_t k = 0; k < k_count; ++k) {
    const fx::Mat34& m = palette[joints[k]];
    const int64_t w = weights[k];
    for (int i = 0; i < 3; ++i) {
      b.m[3 * i + 0] += w * m.m[i][0];
      b.m[3 * i + 1] += w * m.m[i][1];
      b.m[3 * i + 2] += w * m.m[i][2];
      b.t[i] += w * m.t[i];
    }
  }
  int64_t lin[9];
  for (int i = 0; i < 9; ++i) {
    const int64_t e = fx::round_shift(b.m[i], fx::kUnitFracBits);  // Q8.24
    lin[i] = fx::clamp_i64(e, -kLinearLimit, kLinearLimit);
    *saturated += static_cast<uint32_t>(lin[i] != e);
  }
  const int64_t p[3] = {rig.position[0][v], rig.position[1][v], rig.position[2][v]};
  for (int i = 0; i < 3; ++i) {
    // |lin| <= 2^30, |p| < 2^31: three products < 3 * 2^61, plus t << 24 < 2^55.
    const int64_t t = fx::round_shift(b.t[i], fx::kUnitFracBits);  // Q12.20, convex: fits
    const int64_t acc = lin[3 * i] * p[0] + lin[3 * i + 1] * p[1] + lin[3 * i + 2] * p[2] + t * (1 << 24);
    out.position[i][index] = fx::sat_i32(fx::round_shift(acc, fx::kLinFracBits));
  }
  if (!out.normal[0].empty() && !rig.normal[0].empty()) {
    const int64_t n[3] = {rig.normal[0][v], rig.normal[1][v], rig.normal[2][v]};
    int32_t r[3];
    for (int i = 0; i < 3; ++i)
      r[i] = fx::sat_i32(
          fx::round_shift(lin[3 * i] * n[0] + lin[3 * i + 1] * n[1] + lin[3 * i + 2] * n[2], fx::kLinFracBits));
    fx::Vec3 unit;
    fx::normalize_fast({r[0], r[1], r[2]}, &unit);
    out.normal[0][index] = unit.x;
    out.normal[1][index] = unit.y;
    out.normal[2][index] = unit.z;
  }
}

namespace {

using detail::DualMotion;

// One DQS vertex: dual quaternion linear blending (Kavan et al. 2008) with
// its antipodality rule, every quaternion blended on the hemisphere of the
// vertex's first influence. kNearUnit: every real
// component of the palette lies in [-kDualRealLimit, kDualRealLimit], so the
// four products of the hemisphere test sum below 4 (1.25 * 2^30)^2 < 2^63:
// the plain dot equals dot_wide (which only saturates beyond 2^63, keeping
// the sign), without its saturating adds.
template <bool kNearUnit>
void skin_dual_vertex_impl(const rig::Rig& rig, std::span<const fx::DualQuat> dual, uint32_t v,
                           const SkinnedVertices& out, uint32_t index) {
  const uint32_t k_count = rig.influences_per_vertex;
  const uint16_t* joints = rig.influence_palette.data() + size_t{v} * k_count;
  const fx::Unit* weights = rig.influence_weight.data() + size_t{v} * k_count;
  const fx::Quat& pivot = dual[joints[0]].real;
  const int64_t pw = pivot.w, px = pivot.x, py = pivot.y, pz = pivot.z;
  int64_t real[4] = {0, 0, 0, 0}, du[4] = {0, 0, 0, 0};
  for (uint32_t k = 0; k < k_count; ++k) {
    const fx::DualQuat& d = dual[joints[k]];
    const int64_t dot =
        kNearUnit ? pw * d.real.w + px * d.real.x + py * d.real.y + pz * d.real.z : fx::dot_wide(pivot, d.real);
    const int64_t w = dot < 0 ? -int64_t{weights[k]} : int64_t{weights[k]};
    real[0] += w * d.real.w;
    real[1] += w * d.real.x;
    real[2] += w * d.real.y;
    real[3] += w * d.real.z;
    du[0] += w * d.dual.w;
    du[1] += w * d.dual.x;
    du[2] += w * d.dual.y;
    du[3] += w * d.dual.z;
  }
  const auto n30 = [](int64_t x) { return fx::sat_i32(fx::round_shift(x, fx::kUnitFracBits)); };
  const DualMotion motion = detail::dual_motion(
      {{n30(real[0]), n30(real[1]), n30(real[2]), n30(real[3])}, {n30(du[0]), n30(du[1]), n30(du[2]), n30(du[3])}});
  const fx::Rot3& rot = motion.rotation;
  const int64_t(&t)[3] = motion.t;
  // R p (Q20+30) and 2 t (Q50, halved into the shift) rounded together once.
  // 2 t itself may pass 2^63, so t is added twice, saturating: the same value
  // as add_sat_i64(rp, 2 t) wherever 2 t fits (a sum that saturates after
  // one t saturates after both), and defined everywhere.
  const int64_t p[3] = {rig.position[0][v], rig.position[1][v], rig.position[2][v]};
  int64_t rp[3];
  rotate_into(rot, p, rp);
  for (int c = 0; c < 3; ++c)
    out.position[c][index] =
        fx::sat_i32(fx::round_shift(fx::add_sat_i64(fx::add_sat_i64(rp[c], t[c]), t[c]), fx::kUnitFracBits));
  if (!out.normal[0].empty() && !rig.normal[0].empty()) {
    const int64_t n[3] = {rig.normal[0][v], rig.normal[1][v], rig.normal[2][v]};
    int64_t rn[3];
    rotate_into(rot, n, rn);
    for (int c = 0; c < 3; ++c) out.normal[c][index] = fx::sat_i32(fx::round_shift(rn[c], fx::kUnitFracBits));
  }
}

// LBS vertices of the range (DQS ones skipped when skip_dual).
uint32_t skin_linear_scalar(const rig::Rig& rig, std::span<const fx::Mat34> palette, bool skip_dual, uint32_t first,
                            uint32_t count, const SkinnedVertices& out) {
  uint32_t saturated = 0;
  for (uint32_t i = 0; i < count;) {
    if (skip_dual && detail::is_dual(rig, first + i)) {
      i = detail::skip_dual_run(rig, first, i, count);
      continue;
    }
    detail::skin_linear_vertex(rig, palette, first + i, out, i, &saturated);
    ++i;
  }
  return saturated;
}

}  // namespace

bool detail::dual_palette_near_unit(std::span<const fx::DualQuat> dual) {
  bool near_unit = true;
  for (const fx::DualQuat& d : dual) {
    const int64_t c[4] = {d.real.w, d.real.x, d.real.y, d.real.z};
    for (int64_t x : c) near_unit = near_unit && x >= -kDualRealLimit && x <= kDualRealLimit;
  }
  return near_unit;
}

void detail::skin_dual_vertex(const rig::Rig& rig, std::span<const fx::DualQuat> dual, uint32_t v,
                              const SkinnedVertices& out, uint32_t index, bool near_unit) {
  if (near_unit) {
    skin_dual_vertex_impl<true>(rig, dual, v, out, index);
  } else {
    skin_dual_vertex_impl<false>(rig, dual, v, out, index);
  }
}

void detail::skin_dual_scalar(const rig::Rig& rig, std::span<const fx::DualQuat> dual, uint32_t first, uint32_t count,
                              const SkinnedVertices& out) {
  // The palette's range is checked once per call (once per frame in the engine).
  const bool near_unit = dual_palette_near_unit(dual);
  for (uint32_t i = 0; i < count; ++i) {
    const uint32_t v = first + i;
    if (!detail::is_dual(rig, v)) continue;
    if (near_unit) {
      skin_dual_vertex_impl<true>(rig, dual, v, out, i);
    } else {
      skin_dual_vertex_impl<false>(rig, dual, v, out, i);
    }
  }
}

bool lbs_kernel_supported(LbsKernel kernel) {
  switch (kernel) {
    case LbsKernel::kScalar:
      return true;
    case LbsKernel::kAvx2:
#if defined(__x86_64__)
      return __builtin_cpu_supports("avx2") != 0;  // reads CPUID data, no OS call
#else
      return false;
#endif
    case LbsKernel::kNeon:
#if defined(__aarch64__)
      return true;  // Advanced SIMD is part of every AArch64 CPU
#else
      return false;
#endif
    case LbsKernel::kAvx512:
#if defined(__x86_64__)
      return __builtin_cpu_supports("avx512f") != 0 && __builtin_cpu_supports("avx512vl") != 0 &&
             __builtin_cpu_supports("avx512cd") != 0;
#else
      return false;
#endif
  }
  return false;
}

// The fastest kernel this CPU runs: every kernel writes the same words.
LbsKernel lbs_kernel_default() {
#if defined(__aarch64__)
  return LbsKernel::kNeon;
#else
  // AVX-512 halves the blend's instructions (two 8-lane products per influence, not four 4-lane ones).
  if (lbs_kernel_supported(LbsKernel::kAvx512)) return LbsKernel::kAvx512;
  return lbs_kernel_supported(LbsKernel::kAvx2) ? LbsKernel::kAvx2 : LbsKernel::kScalar;
#endif
}

const char* lbs_kernel_name(LbsKernel kernel) {
  switch (kernel) {
    case LbsKernel::kScalar:
      return "scalar";
    case LbsKernel::kAvx2:
      return "avx2";
    case LbsKernel::kNeon:
      return "neon";
    case LbsKernel::kAvx512:
      return "avx512";
  }
  return "unknown";
}

bool dqs_kernel_supported(DqsKernel kernel) {
  switch (kernel) {
    case DqsKernel::kScalar:
      return true;
    case DqsKernel::kAvx2:
      return lbs_kernel_supported(LbsKernel::kAvx2);
    case DqsKernel::kAvx512:
      return lbs_kernel_supported(LbsKernel::kAvx512);  // the same extensions
  }
  return false;
}

DqsKernel dqs_kernel_default() {
  if (dqs_kernel_supported(DqsKernel::kAvx512)) return DqsKernel::kAvx512;
  return dqs_kernel_supported(DqsKernel::kAvx2) ? DqsKernel::kAvx2 : DqsKernel::kScalar;
}

const char* dqs_kernel_name(DqsKernel kernel) {
  switch (kernel) {
    case DqsKernel::kScalar:
      return "scalar";
    case DqsKernel::kAvx2:
      return "avx2";
    case DqsKernel::kAvx512:
      return "avx512";
  }
  return "unknown";
}

// Every vertex is written by exactly one of the two passes, and each vertex's
// words depend on nothing but its own inputs: the passes' order is free.
uint32_t skin_vertices(LbsKernel lbs, DqsKernel dqs, const rig::Rig& rig, std::span<const fx::Mat34> palette,
                       std::span<const fx::DualQuat> dual_palette, uint32_t first, uint32_t count,
                       const SkinnedVertices& out) {
  const bool dual_ready = !dual_palette.empty();
  uint32_t saturated = 0;
#if defined(__x86_64__)
  if (lbs == LbsKernel::kAvx512 && lbs_kernel_supported(LbsKernel::kAvx512)) {
    saturated = detail::skin_linear_avx512(rig, palette, dual_ready, first, count, out);
  } else if (lbs == LbsKernel::kAvx2 && lbs_kernel_supported(LbsKernel::kAvx2)) {
    saturated = detail::skin_linear_avx2(rig, palette, dual_ready, first, count, out);
  } else {
    saturated = skin_linear_scalar(rig, palette, dual_ready, first, count, out);
  }
  if (dual_ready) {
    if (dqs == DqsKernel::kAvx512 && dqs_kernel_supported(DqsKernel::kAvx512)) {
      detail::skin_dual_avx512(rig, dual_palette, first, count, out);
    } else if (dqs == DqsKernel::kAvx2 && dqs_kernel_supported(DqsKernel::kAvx2)) {
      detail::skin_dual_avx2(rig, dual_palette, first, count, out);
    } else {
      detail::skin_dual_scalar(rig, dual_palette, first, count, out);
    }
  }
#else
  (void)dqs;
#if defined(__aarch64__)
  if (lbs == LbsKernel::kNeon) {
    saturated = detail::skin_linear_neon(rig, palette, dual_ready, first, count, out);
  } else {
    saturated = skin_linear_scalar(rig, palette, dual_ready, first, count, out);
  }
#else
  (void)lbs;
  saturated = skin_linear_scalar(rig, palette, dual_ready, first, count, out);
#endif
  if (dual_ready) detail::skin_dual_scalar(rig, dual_palette, first, count, out);
#endif
  return saturated;
}

uint32_t skin_vertices(LbsKernel kernel, const rig::Rig& rig, std::span<const fx::Mat34> palette,
                       std::span<const fx::DualQuat> dual_palette, uint32_t first, uint32_t count,
                       const SkinnedVertices& out) {
  // The DQS kernel of the same extension.
  const DqsKernel dqs = kernel == LbsKernel::kAvx512 ? DqsKernel::kAvx512
                        : kernel == LbsKernel::kAvx2 ? DqsKernel::kAvx2
                                                     : DqsKernel::kScalar;
  return skin_vertices(kernel, dqs, rig, palette, dual_palette, first, count, out);
}

uint32_t skin_vertices(const rig::Rig& rig, std::span<const fx::Mat34> palette,
                       std::span<const fx::DualQuat> dual_palette, uint32_t first, uint32_t count,
                       const SkinnedVertices& out) {
  return skin_vertices(lbs_kernel_default(), dqs_kernel_default(), rig, palette, dual_palette, first, count, out);
}

}  // namespace sinew::skin
