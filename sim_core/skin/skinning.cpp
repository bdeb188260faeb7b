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

void detail::skin_dual_vertex(const rig::Rig& rig, std::span<const fx::DualQuat> dual, uint32_t v,
                              const SkinnedVertices& out, uint32_t index) {
  const uint32_t k_count = rig.influences_per_vertex;
  const uint16_t* joints = rig.influence_palette.data() + size_t{v} * k_count;
  const fx::Unit* weights = rig.influence_weight.data() + size_t{v} * k_count;
  const fx::Quat& pivot = dual[joints[0]].real;
  int64_t real[4] = {0, 0, 0, 0}, du[4] = {0, 0, 0, 0};
  for (uint32_t k = 0; k < k_count; ++k) {
    const fx::DualQuat& d = dual[joints[k]];
    // Antipodality: blend every quaternion on the pivot's hemisphere.
    const int64_t w = fx::dot_wide(pivot, d.real) < 0 ? -int64_t{weights[k]} : int64_t{weights[k]};
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
  fx::DualQuat b{{n30(real[0]), n30(real[1]), n30(real[2]), n30(real[3])},
                 {n30(du[0]), n30(du[1]), n30(du[2]), n30(du[3])}};
  fx::normalize_fast(&b);
  // One rotation matrix for point and normal; the translation in closed form,
  // t = 2 (w d_v - d_w r_v + r_v x d_v), from exact Q50 products rounded once.
  const fx::Rot3 rot = fx::rot3_of_unit(b.real);  // normalize_fast leaves it within a few LSB of unit
  const int64_t rw = b.real.w, rx = b.real.x, ry = b.real.y, rz = b.real.z;
  const int64_t dw = b.dual.w, dx = b.dual.x, dy = b.dual.y, dz = b.dual.z;
  const int64_t t[3] = {rw * dx - dw * rx + (ry * dz - rz * dy), rw * dy - dw * ry + (rz * dx - rx * dz),
                        rw * dz - dw * rz + (rx * dy - ry * dx)};
  // R p (Q20+30) and 2 t (Q50, halved into the shift) rounded together once.
  const int64_t p[3] = {rig.position[0][v], rig.position[1][v], rig.position[2][v]};
  int64_t rp[3];
  rotate_into(rot, p, rp);
  for (int c = 0; c < 3; ++c)
    out.position[c][index] = fx::sat_i32(fx::round_shift(fx::add_sat_i64(rp[c], 2 * t[c]), fx::kUnitFracBits));
  if (!out.normal[0].empty() && !rig.normal[0].empty()) {
    const int64_t n[3] = {rig.normal[0][v], rig.normal[1][v], rig.normal[2][v]};
    int64_t rn[3];
    rotate_into(rot, n, rn);
    for (int c = 0; c < 3; ++c) out.normal[c][index] = fx::sat_i32(fx::round_shift(rn[c], fx::kUnitFracBits));
  }
}

namespace {

uint32_t skin_vertices_scalar(const rig::Rig& rig, std::span<const fx::Mat34> palette,
                              std::span<const fx::DualQuat> dual_palette, uint32_t first, uint32_t count,
                              const SkinnedVertices& out) {
  uint32_t saturated = 0;
  const bool dual_ready = !dual_palette.empty();
  for (uint32_t i = 0; i < count; ++i) {
    const uint32_t v = first + i;
    if (dual_ready && rig.method[v] == static_cast<uint8_t>(rig::SkinMethod::kDualQuaternion)) {
      detail::skin_dual_vertex(rig, dual_palette, v, out, i);
    } else {
      detail::skin_linear_vertex(rig, palette, v, out, i, &saturated);
    }
  }
  return saturated;
}

}  // namespace

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
  }
  return false;
}

// The fastest kernel this CPU runs: every kernel writes the same words.
LbsKernel lbs_kernel_default() {
#if defined(__aarch64__)
  return LbsKernel::kNeon;
#else
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
  }
  return "unknown";
}

uint32_t skin_vertices(LbsKernel kernel, const rig::Rig& rig, std::span<const fx::Mat34> palette,
                       std::span<const fx::DualQuat> dual_palette, uint32_t first, uint32_t count,
                       const SkinnedVertices& out) {
#if defined(__x86_64__)
  if (kernel == LbsKernel::kAvx2 && lbs_kernel_supported(LbsKernel::kAvx2))
    return detail::skin_vertices_avx2(rig, palette, dual_palette, first, count, out);
#elif defined(__aarch64__)
  if (kernel == LbsKernel::kNeon) return detail::skin_vertices_neon(rig, palette, dual_palette, first, count, out);
#else
  (void)kernel;
#endif
  return skin_vertices_scalar(rig, palette, dual_palette, first, count, out);
}

uint32_t skin_vertices(const rig::Rig& rig, std::span<const fx::Mat34> palette,
                       std::span<const fx::DualQuat> dual_palette, uint32_t first, uint32_t count,
                       const SkinnedVertices& out) {
  return skin_vertices(lbs_kernel_default(), rig, palette, dual_palette, first, count, out);
}

}  // namespace sinew::skin
