// Smoothing kernels of Mueller, Charypar and Gross 2003 (the paper's [37]), in
// normalised form: each takes s = q^2 with q = distance / h in Q2.30, s in
// [0, 1], and omits the constants (they fold into the particle mass and the
// gains of SphParams). Working in units of h keeps every value in [0, ~32]:
// fixed point neither overflows nor underflows whatever the rig's units.
//   poly6:      W  ~ (1 - q^2)^3            (density)
//   spiky grad: dW ~ (1 - q)^2 / q * (r/h)  (pressure; factor tabulated)
//   viscosity:  L  ~ (1 - q)                (viscosity Laplacian)
//   colour:     grad (1 - q^2)^3      = -6 (1 - q^2)^2 (r/h)
//               laplacian (1 - q^2)^3 = -6 (1 - q^2) (3 - 7 q^2)
//               (Mueller 2003 §4.4: the poly6 colour field's gradient and
//               Laplacian, with respect to r/h; polynomials in s, no table)
// The two kernels that need q itself come from 1025-entry tables over s
// (built at compile time with an exact integer sqrt) with linear
// interpolation: pure integer, identical on every platform.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "sim_core/fixed/scalar.hpp"
#include "sim_core/fixed/sqrt.hpp"

namespace sinew::sph {

namespace kernel_detail {

inline constexpr int kTableBits = 10;  // 1024 intervals over s in [0, 1]
inline constexpr int kStepShift = 30 - kTableBits;
inline constexpr size_t kTableSize = (size_t{1} << kTableBits) + 1;

// q in Q30 for s in Q30.
constexpr int64_t q_of(int64_t s) { return static_cast<int64_t>(fx::isqrt_u64(static_cast<uint64_t>(s) << 30)); }

// (1 - q)^2 / q in Q24; below the first table step q is clamped to 1/32
// (coincident particles have no direction anyway).
constexpr std::array<int32_t, kTableSize> make_spiky() {
  std::array<int32_t, kTableSize> t{};
  for (size_t i = 0; i < kTableSize; ++i) {
    const int64_t s = static_cast<int64_t>(i == 0 ? 1 : i) << kStepShift;
    const int64_t q = q_of(s), one = int64_t{1} << 30;
    const int64_t num = (one - q) * (one - q);  // Q60
    t[i] = static_cast<int32_t>((num / q + 32) >> 6);
  }
  return t;
}

// 1 - q in Q30.
constexpr std::array<int32_t, kTableSize> make_viscosity() {
  std::array<int32_t, kTableSize> t{};
  for (size_t i = 0; i < kTableSize; ++i)
    t[i] = static_cast<int32_t>((int64_t{1} << 30) - q_of(static_cast<int64_t>(i) << kStepShift));
  return t;
}

inline constexpr std::array<int32_t, kTableSize> kSpiky = make_spiky();
inline constexpr std::array<int32_t, kTableSize> kViscosity = make_viscosity();

inline int32_t lookup(const std::array<int32_t, kTableSize>& t, uint32_t s) {
  const uint32_t i = s >> kStepShift;
  if (i >= kTableSize - 1) return t[kTableSize - 1];
  const int64_t frac = s & ((uint32_t{1} << kStepShift) - 1);
  const int64_t a = t[i], b = t[i + 1];
  return static_cast<int32_t>(a + fx::round_shift((b - a) * frac, kStepShift));
}

}  // namespace kernel_detail

// s = q^2 in Q2.30, s < 2^30 (inside the kernel). Result in Q2.30.
inline int32_t poly6(uint32_t s) {
  const int64_t t = (int64_t{1} << 30) - s;
  const int64_t t2 = fx::round_shift(t * t, 30);
  return static_cast<int32_t>(fx::round_shift(t2 * t, 30));
}

// (1 - q)^2 / q in Q8.24.
inline int32_t spiky_factor(uint32_t s) { return kernel_detail::lookup(kernel_detail::kSpiky, s); }

// (1 - q) in Q2.30.
inline int32_t viscosity_factor(uint32_t s) { return kernel_detail::lookup(kernel_detail::kViscosity, s); }

// Both factors at once (one table position): the same words as
// spiky_factor(s) and viscosity_factor(s).
inline void kernel_factors(uint32_t s, int32_t* spiky, int32_t* viscosity) {
  using namespace kernel_detail;
  const uint32_t i = s >> kStepShift;
  if (i >= kTableSize - 1) {
    *spiky = kSpiky[kTableSize - 1];
    *viscosity = kViscosity[kTableSize - 1];
    return;
  }
  const int64_t frac = s & ((uint32_t{1} << kStepShift) - 1);
  const int64_t a = kSpiky[i], b = kSpiky[i + 1], c = kViscosity[i], d = kViscosity[i + 1];
  *spiky = static_cast<int32_t>(a + fx::round_shift((b - a) * frac, kStepShift));
  *viscosity = static_cast<int32_t>(c + fx::round_shift((d - c) * frac, kStepShift));
}

// Colour-field factors at s = q^2 (Q2.30, s < 2^30), both Q30 and without
// the common factor -6: gradient (1 - s)^2 in [0, 1] and Laplacian
// (1 - s)(3 - 7 s) in [-4/7, 3] (int64: it exceeds Q2.30's range at s = 0).
inline void colour_factors(uint32_t s, int64_t* gradient, int64_t* laplacian) {
  const int64_t t = (int64_t{1} << 30) - s;  // 1 - s, Q30, in (0, 2^30]
  *gradient = fx::round_shift(t * t, 30);
  *laplacian = fx::round_shift(t * ((int64_t{3} << 30) - 7 * int64_t{s}), 30);
}

// Normalised offset (a - b) / h in Q2.30 and s = q^2 in Q2.30 for two
// positions closer than h on every axis; false (and nothing written) when
// they are not within the kernel. inv_h: 2^50 / h, rounded (see InvH).
struct PairGeometry {
  fx::Vec3 d;  // (a - b) / h, Q2.30, each component in (-1, 1)
  uint32_t s;  // |d|^2, Q2.30, < 2^30
};

struct InvH {
  int64_t inv = 0;  // round(2^50 / h)
  fx::Len h = 0;
};

inline InvH make_inv_h(fx::Len h) { return {fx::div_round(int64_t{1} << 50, h), h}; }

inline bool pair_geometry(fx::Vec3 a, fx::Vec3 b, const InvH& ih, PairGeometry* out) {
  const int64_t dx = int64_t{a.x} - b.x, dy = int64_t{a.y} - b.y, dz = int64_t{a.z} - b.z;
  if (dx >= ih.h || dx <= -ih.h || dy >= ih.h || dy <= -ih.h || dz >= ih.h || dz <= -ih.h) return false;
  // |d| < h < 2^31 and inv < 2^50 / h, so the products stay below 2^50.
  const int64_t nx = fx::round_shift(dx * ih.inv, 20), ny = fx::round_shift(dy * ih.inv, 20),
                nz = fx::round_shift(dz * ih.inv, 20);
  const int64_t s = fx::round_shift(nx * nx + ny * ny + nz * nz, 30);
  if (s >= (int64_t{1} << 30)) return false;
  out->d = {static_cast<int32_t>(nx), static_cast<int32_t>(ny), static_cast<int32_t>(nz)};
  out->s = static_cast<uint32_t>(s);
  return true;
}

}  // namespace sinew::sph
