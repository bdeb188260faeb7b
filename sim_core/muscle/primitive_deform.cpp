#include "primitive_deform.hpp"

#include "sim_core/fixed/wide.hpp"

namespace sinew::muscle {
namespace {

constexpr int64_t kOne = int64_t{1} << fx::kUnitFracBits;
constexpr int64_t kDirectionLimit = int64_t{1} << 30;
// 2^33 / (2 pi): binary angle per radian, times 2 (R = c * this / (2 bend)).
constexpr int64_t kTwoBinaryPerRadian = 1367130551;
// 2 pi in Q3.29: a binary angle times this >> 32 is radians in Q29.
constexpr int64_t kTwoPiQ29 = 3373259426;

int64_t mul30(int64_t a, int64_t b) { return fx::mul_shift_round(a, b, fx::kUnitFracBits); }

// sin and cos of a signed binary angle held in an int64 (|a| < 2^31).
fx::SinCos sin_cos_of(int64_t a) { return fx::sin_cos(static_cast<fx::Angle>(static_cast<uint64_t>(a))); }

int64_t clamp_to(int64_t v, int64_t limit) { return fx::clamp_i64(v, -limit, limit); }

}  // namespace

int64_t bend_radius(int64_t half_height, int64_t bend) {
  return fx::div_round(half_height * kTwoBinaryPerRadian, 2 * bend);
}

void narrow_direction(int64_t g[3]) {
  uint64_t largest = 0;
  for (int i = 0; i < 3; ++i)
    if (fx::magnitude(g[i]) > largest) largest = fx::magnitude(g[i]);
  int shift = 0;
  while ((largest >> shift) >= static_cast<uint64_t>(kDirectionLimit)) ++shift;
  if (shift == 0) return;
  for (int i = 0; i < 3; ++i) g[i] = fx::round_shift(g[i], shift);
  // Rounding up may reach 2^30 exactly: one more halving keeps the bound.
  for (int i = 0; i < 3; ++i)
    if (fx::magnitude(g[i]) >= static_cast<uint64_t>(kDirectionLimit)) {
      for (int k = 0; k < 3; ++k) g[k] /= 2;
      break;
    }
}

bool primitive_undeform(const PrimitiveFrame& f, const int64_t local[3], DeformTrace* t) {
  const PrimitiveDeformation& d = f.deformation;
  const int64_t c = f.extent[2];
  int64_t x = local[0], y = local[1], z = local[2];
  t->unbent_x = x;
  if (d.bend != 0) {
    // Inverse bend (Barr 84): the angle about the bend's centre (R, 0),
    // clamped to the bent range, then the rigid rotation back.
    const int64_t radius = bend_radius(c, d.bend);
    const int64_t u = x - radius, w = z;
    const int64_t sy = radius > 0 ? w : -w, sx = radius > 0 ? -u : u;
    int shift = 0;  // atan2 is scale free: bring both into int32
    while ((fx::magnitude(sy) >> shift) >= (uint64_t{1} << 30) || (fx::magnitude(sx) >> shift) >= (uint64_t{1} << 30))
      ++shift;
    const int64_t bend = d.bend;
    const int64_t theta = clamp_to(
        fx::angle_signed(fx::atan2_angle(static_cast<int32_t>(sy >> shift), static_cast<int32_t>(sx >> shift))),
        bend < 0 ? -bend : bend);
    const fx::SinCos sc = sin_cos_of(theta);
    const int64_t axial = fx::div_round(theta * c, bend);  // zh = theta / k
    x = mul30(sc.cos, u) - mul30(sc.sin, w) + radius;
    z = axial + mul30(sc.sin, u) + mul30(sc.cos, w);
    t->bend = sc;
    t->unbent_x = x;
  }
  if (z >= c || z <= -c) return false;
  if (d.twist != 0) {
    const fx::SinCos sc = sin_cos_of(fx::div_round(int64_t{d.twist} * z, c));
    const int64_t x1 = mul30(sc.cos, x) + mul30(sc.sin, y);
    y = mul30(sc.cos, y) - mul30(sc.sin, x);
    x = x1;
    t->twist = sc;
  }
  t->tapered[0] = x;
  t->tapered[1] = y;
  t->tapered[2] = z;
  const int64_t a2 = 2 * int64_t{f.extent[0]}, b2 = 2 * int64_t{f.extent[1]};
  if (x >= a2 || x <= -a2 || y >= b2 || y <= -b2) return false;
  if (d.taper != 0) {
    const int64_t r = kOne + fx::div_round(int64_t{d.taper} * z, c);  // [1/2, 3/2]
    x = fx::div_round(x * kOne, r);
    y = fx::div_round(y * kOne, r);
    t->taper_r = static_cast<fx::Unit>(r);
  }
  t->undeformed[0] = x;
  t->undeformed[1] = y;
  t->undeformed[2] = z;
  return true;
}

void primitive_deform(const PrimitiveFrame& f, const int64_t in[3], int64_t out[3]) {
  const PrimitiveDeformation& d = f.deformation;
  const int64_t c = f.extent[2];
  int64_t x = in[0], y = in[1];
  const int64_t z = in[2];
  const int64_t zh = clamp_to(z, c);
  if (d.taper != 0) {
    const int64_t r = kOne + fx::div_round(int64_t{d.taper} * zh, c);
    x = mul30(r, x);
    y = mul30(r, y);
  }
  if (d.twist != 0) {
    const fx::SinCos sc = sin_cos_of(fx::div_round(int64_t{d.twist} * zh, c));
    const int64_t x2 = mul30(sc.cos, x) - mul30(sc.sin, y);
    y = mul30(sc.sin, x) + mul30(sc.cos, y);
    x = x2;
  }
  out[1] = y;
  if (d.bend == 0) {
    out[0] = x;
    out[2] = z;
    return;
  }
  const int64_t radius = bend_radius(c, d.bend);
  const fx::SinCos sc = sin_cos_of(fx::div_round(int64_t{d.bend} * zh, c));
  const int64_t a = x - radius, b = z - zh;
  out[0] = radius + mul30(sc.cos, a) + mul30(sc.sin, b);
  out[2] = mul30(sc.cos, b) - mul30(sc.sin, a);
}

void primitive_deform_gradient(const PrimitiveFrame& f, const DeformTrace& t, int64_t g[3]) {
  const PrimitiveDeformation& d = f.deformation;
  const int64_t c = f.extent[2];
  narrow_direction(g);
  if (d.taper != 0) {
    // r J^T g = (gx, gy, r gz - (taper / c) (x0 gx + y0 gy)); |x0| < 2^32.
    const int64_t dot = fx::mul_shift_round(t.undeformed[0], g[0], 4) + fx::mul_shift_round(t.undeformed[1], g[1], 4);
    const int64_t term = fx::div_round(mul30(dot, d.taper), c) * 16;
    g[2] = mul30(t.taper_r, g[2]) - term;
    narrow_direction(g);
  }
  if (d.twist != 0) {
    // J^T g = (C gx - S gy, S gx + C gy, gz + theta' (y1 gx - x1 gy)),
    // theta' = twist (radians) / c.
    const int64_t twist_q29 = fx::mul_shift_round(d.twist, kTwoPiQ29, 32);
    const int64_t cross = fx::mul_shift_round(t.tapered[1], g[0], 4) - fx::mul_shift_round(t.tapered[0], g[1], 4);
    const int64_t term = fx::div_round(fx::mul_shift_round(cross, twist_q29, 29), c) * 16;
    const int64_t gx = mul30(t.twist.cos, g[0]) - mul30(t.twist.sin, g[1]);
    const int64_t gy = mul30(t.twist.sin, g[0]) + mul30(t.twist.cos, g[1]);
    g[0] = gx;
    g[1] = gy;
    g[2] += term;
    narrow_direction(g);
  }
  if (d.bend != 0) {
    // (1 - k x2) J^T g = (s C gx + S gz, s gy, -s S gx + C gz), s = 1 - x2 / R > 0.
    const int64_t radius = bend_radius(c, d.bend);
    const int64_t s28 = (int64_t{1} << 28) - fx::div_round(t.unbent_x * (int64_t{1} << 28), radius);
    const int64_t fx_ = fx::mul_shift_round(s28, g[0], 28);
    g[1] = fx::mul_shift_round(s28, g[1], 28);
    const int64_t gx = mul30(t.bend.cos, fx_) + mul30(t.bend.sin, g[2]);
    g[2] = mul30(t.bend.cos, g[2]) - mul30(t.bend.sin, fx_);
    g[0] = gx;
    narrow_direction(g);
  }
}

}  // namespace sinew::muscle
