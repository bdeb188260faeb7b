#include "primitive.hpp"

#include "vec_ops.hpp"

namespace sinew::muscle {
namespace {

constexpr int64_t kOne = int64_t{1} << fx::kUnitFracBits;
constexpr int64_t kOutsideBox = int64_t{4} << fx::kUnitFracBits;

struct Powers {
  fx::Unit p;         // q^p
  fx::Unit p_minus1;  // q^(p-1), carries the sign of q
};

int32_t comp(fx::Vec3 v, int c) { return c == 0 ? v.x : (c == 1 ? v.y : v.z); }

Powers powers(fx::Unit q, int exponent) {
  const fx::Unit q2 = fx::mul_unit(q, q);
  if (exponent == 2) return {q2, q};
  const fx::Unit q4 = fx::mul_unit(q2, q2);
  if (exponent == 4) return {q4, fx::mul_unit(q2, q)};
  if (exponent == 6) return {fx::mul_unit(q4, q2), fx::mul_unit(q4, q)};
  return {fx::mul_unit(q4, q4), fx::mul_unit(fx::mul_unit(q4, q2), q)};
}

}  // namespace

PrimitiveSample primitive_sample(const PrimitiveFrame& f, fx::Vec3 p) {
  PrimitiveSample s;
  s.value = kOutsideBox;
  const bool cylinder = f.kind == static_cast<uint8_t>(PrimitiveKind::kCylinder);
  const int exponent = f.kind == static_cast<uint8_t>(PrimitiveKind::kSuperellipsoid) ? f.exponent : 2;
  const fx::Vec3 d = fx::sub(p, f.centre);
  int64_t local[3];
  fx::Len emax = 1;
  for (int i = 0; i < 3; ++i) {
    if (f.extent[i] <= 0) return s;
    local[i] = component(d, f.axis[i]);
    // Outside the bounding box every term (or the cylinder's cap test) is >= 1.
    if (local[i] >= f.extent[i] || local[i] <= -int64_t{f.extent[i]}) return s;
    if (f.extent[i] > emax) emax = f.extent[i];
  }
  const int terms = cylinder ? 2 : 3;
  int64_t value = 0;
  int32_t g[3] = {0, 0, 0};
  for (int i = 0; i < terms; ++i) {
    const fx::Unit q = fx::sat_i32(fx::div_round(local[i] * kOne, f.extent[i]));  // |q| < 1
    const Powers pw = powers(q, exponent);
    value += pw.p;
    // dF/dx_i * emax = p q^(p-1) * (emax / a_i): Q2.30 x Q16 ratio -> Q20.
    const int64_t ratio = fx::div_round(int64_t{emax} << 16, f.extent[i]);  // <= 2^16 * aspect
    g[i] = fx::sat_i32(fx::round_shift(int64_t{exponent} * pw.p_minus1 * ratio, 26));
  }
  s.value = value;
  s.inside = value < kOne;
  const fx::Vec3 g_local{g[0], g[1], g[2]};
  s.gradient_length = fx::sat_i32(fx::length(g_local));
  fx::Vec3 n{};
  if (fx::normalize_to_unit(g_local, &n)) {
    const auto world = [&](int c) {
      const int64_t sum =
          int64_t{comp(f.axis[0], c)} * n.x + int64_t{comp(f.axis[1], c)} * n.y + int64_t{comp(f.axis[2], c)} * n.z;
      return fx::sat_i32(fx::round_shift(sum, fx::kUnitFracBits));
    };
    s.normal = {world(0), world(1), world(2)};
  }
  return s;
}

fx::Vec3 primitive_push_out(const PrimitiveFrame& f, fx::Vec3 p, fx::Vec3 fallback, int newton_steps) {
  fx::Len emax = 0;
  for (int i = 0; i < 3; ++i)
    if (f.extent[i] > emax) emax = f.extent[i];
  for (int step = 0; step < newton_steps; ++step) {
    const PrimitiveSample s = primitive_sample(f, p);
    if (!s.inside) break;
    fx::Vec3 dir = s.normal;
    int64_t delta = emax / 2;
    if (s.gradient_length > 0 && !(dir == fx::Vec3{0, 0, 0})) {
      // Newton on F along the gradient: delta = (1 - F) / |grad F|; F is
      // convex, so the step lands on or just past the surface. +1 LSB makes
      // a point on the surface leave it.
      delta = fx::div_round((kOne - s.value) * emax, int64_t{s.gradient_length} << 10) + 1;
    } else {
      dir = fallback;
    }
    if (delta > emax) delta = emax;
    p = fx::add(p, along(dir, fx::sat_i32(delta)));
  }
  return p;
}

}  // namespace sinew::muscle
