#include "primitive.hpp"

#include "primitive_deform.hpp"
#include "sim_core/fixed/rsqrt_fast.hpp"
#include "sim_core/fixed/sqrt.hpp"
#include "sim_core/fixed/wide.hpp"
#include "superquadric.hpp"
#include "vec_ops.hpp"

namespace sinew::muscle {
namespace {

constexpr int64_t kOne = int64_t{1} << fx::kUnitFracBits;
constexpr int64_t kOutsideBox = int64_t{4} << fx::kUnitFracBits;
// Largest emax / extent (Q16) entering a gradient: aspect ratio 8192.
constexpr int64_t kMaxGradientRatio = int64_t{1} << 29;

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
  return {fx::mul_unit(q4, q4), fx::mul_unit(fx::mul_unit(q4, q2), q)};
}

// The exact kernel for one exponent p in {2, 4, 8} (spheres, cylinders):
// fills s's value, inside and gradient_length and g; returns g narrowed.
// With value_only, a point outside (F >= 1) gets its value alone: the
// push-out and the inside count read nothing else of it.
fx::Vec3 exact_gradient(const PrimitiveFrame& f, bool cylinder, int exponent, fx::Len emax, const int64_t local[3],
                        int64_t g[3], PrimitiveSample* out, bool value_only) {
  PrimitiveSample& s = *out;
  const int terms = cylinder ? 2 : 3;
  int64_t value = 0;
  Powers pw[3] = {};
  for (int i = 0; i < terms; ++i) {
    const fx::Unit q = fx::sat_i32(fx::div_round(local[i] * kOne, f.extent[i]));  // |q| < 1
    pw[i] = powers(q, exponent);
    value += pw[i].p;
  }
  s.value = value;
  s.inside = value < kOne;
  if (value_only && !s.inside) return {0, 0, 0};
  uint64_t largest = 0;
  for (int i = 0; i < terms; ++i) {
    // emax / a_i in Q16, for the push-out direction of the reaction
    // constraints (leman-layered-elastic-characters §3). A validated
    // primitive's aspect is <= 64 (2^22), but a muscle-attached one's extents
    // follow the muscle (Z by present / rest length), so the ratio is capped
    // at 2^29 (aspect 8192): g stays below 2^3 * 2^30 * 2^29 = 2^62. Below
    // the cap the value is exact, as before; beyond it the thin axes' share
    // of the gradient direction is too small.
    const int64_t ratio = fx::clamp_i64(fx::div_round(int64_t{emax} << 16, f.extent[i]), 0, kMaxGradientRatio);
    g[i] = int64_t{exponent} * pw[i].p_minus1 * ratio;
    const uint64_t m = fx::magnitude(g[i]);
    if (m > largest) largest = m;
  }
  // Keep the gradient's direction exact whatever its size: shift it so the
  // largest component has 30 significant bits, normalise, remember the shift.
  int shift = 0;
  while ((largest >> shift) >= (uint64_t{1} << 30)) ++shift;
  const auto narrow = [&](int64_t v) { return fx::sat_i32(shift > 0 ? fx::round_shift(v, shift) : v); };
  const fx::Vec3 g_local{narrow(g[0]), narrow(g[1]), narrow(g[2])};
  // |grad F| * emax in Q20: |g| (Q46 >> shift) shifted to 20 fractional bits.
  const int64_t glen = fx::length(g_local);
  s.gradient_length = fx::sat_i32(shift >= 26 ? glen << (shift - 26) : fx::round_shift(glen, 26 - shift));
  return g_local;
}

// The outward normal from the local gradient g (narrowed: g_local), through
// the deformation's covariant transform when there is one, in world axes.
PrimitiveSample finish_sample(const PrimitiveFrame& f, bool deformed, const DeformTrace& trace, int64_t g[3],
                              fx::Vec3 g_local, PrimitiveSample s) {
  fx::Vec3 n{};
  fx::Vec3 direction = g_local;
  if (deformed) {  // the covariant transform J^T grad F (§6.11)
    primitive_deform_gradient(f, trace, g);
    direction = {fx::sat_i32(g[0]), fx::sat_i32(g[1]), fx::sat_i32(g[2])};
  }
  if (fx::normalize_to_unit(direction, &n)) {
    const auto world = [&](int c) {
      const int64_t sum =
          int64_t{comp(f.axis[0], c)} * n.x + int64_t{comp(f.axis[1], c)} * n.y + int64_t{comp(f.axis[2], c)} * n.z;
      return fx::sat_i32(fx::round_shift(sum, fx::kUnitFracBits));
    };
    s.normal = {world(0), world(1), world(2)};
  }
  return s;
}

// primitive_sample; a general superquadric also leaves its evaluation in
// *general (the push-out's Newton step reads it). value_only: see
// exact_gradient.
PrimitiveSample sample(const PrimitiveFrame& f, fx::Vec3 p, SuperquadricEval* general, bool value_only = false) {
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
    if (f.extent[i] > emax) emax = f.extent[i];
  }
  // A deformed primitive tests the undeformed point D^-1(p) (§6.11).
  const bool deformed = is_deformed(f.deformation);
  DeformTrace trace;
  if (deformed) {
    if (!primitive_undeform(f, local, &trace)) return s;
    for (int i = 0; i < 3; ++i) local[i] = trace.undeformed[i];
  }
  // Outside the bounding box every term (or the cylinder's cap test) is >= 1.
  for (int i = 0; i < 3; ++i)
    if (local[i] >= f.extent[i] || local[i] <= -int64_t{f.extent[i]}) return s;
  int64_t g[3] = {0, 0, 0};  // dF/dx_i * emax = p q^(p-1) (emax / a_i), Q2.30 x Q16 -> Q46
  fx::Vec3 g_local{};
  if (is_general_superquadric(f)) {
    *general = superquadric_eval(f, local);
    s.value = general->value;
    s.inside = general->inside;
    for (int i = 0; i < 3; ++i) g[i] = general->g[i];  // |g_i| <= 2^30
    g_local = {static_cast<int32_t>(g[0]), static_cast<int32_t>(g[1]), static_cast<int32_t>(g[2])};
    s.gradient_length = general->gradient_length;
  } else {
    g_local = exact_gradient(f, cylinder, exponent, emax, local, g, &s, value_only);
    if (value_only && !s.inside) return s;
  }
  return finish_sample(f, deformed, trace, g, g_local, s);
}

fx::Vec3 push_out_deformed(const PrimitiveFrame& f, fx::Vec3 p, fx::Vec3 fallback, int newton_steps);

}  // namespace

PrimitiveSample primitive_sample(const PrimitiveFrame& f, fx::Vec3 p) {
  SuperquadricEval general;
  return sample(f, p, &general);
}

int64_t primitive_value(const PrimitiveFrame& f, fx::Vec3 p) {
  SuperquadricEval general;
  return sample(f, p, &general, true).value;
}

fx::Vec3 primitive_push_out(const PrimitiveFrame& f, fx::Vec3 p, fx::Vec3 fallback, int newton_steps) {
  if (is_deformed(f.deformation)) return push_out_deformed(f, p, fallback, newton_steps);
  fx::Len emax = 0;
  for (int i = 0; i < 3; ++i)
    if (f.extent[i] > emax) emax = f.extent[i];
  const int exponent = f.kind == static_cast<uint8_t>(PrimitiveKind::kSuperellipsoid) ? f.exponent : 2;
  const bool general = is_general_superquadric(f);
  for (int step = 0; step < newton_steps; ++step) {
    SuperquadricEval q;
    const PrimitiveSample s = sample(f, p, &q, true);
    if (!s.inside) break;
    if (general) {  // the same Newton step on G = F^(1/p_z), in the log domain (superquadric.hpp)
      fx::Vec3 dir = s.normal;
      int64_t delta = emax / 2;
      if (!(dir == fx::Vec3{0, 0, 0})) {  // the log-domain step needs no gradient_length (it may underflow)
        const int64_t step_len = superquadric_newton_step(f, q);
        delta = step_len < emax ? step_len + 1 : emax;  // +1 LSB: leave the surface
      } else {
        dir = fallback;
      }
      if (delta > emax) delta = emax;
      p = fx::add(p, along(dir, fx::sat_i32(delta)));
      continue;
    }
    // Newton along the gradient on G = F^(1/p), which grows linearly along
    // rays from the centre (F is homogeneous of degree p): a step lands on
    // the surface for radial gradients and close to it otherwise, where
    // Newton on F itself would overshoot. delta = (1 - G) / |grad G|
    // = p (1 - r) F / (r |grad F|), r = F^(1/p) by repeated square roots.
    uint64_t r = static_cast<uint64_t>(s.value);
    for (int e = exponent; e > 1; e /= 2) r = fx::isqrt_fast(r << fx::kUnitFracBits);
    fx::Vec3 dir = s.normal;
    int64_t delta = emax / 2;
    const int64_t den = fx::round_shift(static_cast<int64_t>(r) * s.gradient_length, fx::kUnitFracBits);
    if (den > 0 && !(dir == fx::Vec3{0, 0, 0})) {
      const int64_t num = fx::round_shift(int64_t{exponent} * (kOne - static_cast<int64_t>(r)) * s.value, 30);
      delta = fx::div_round(fx::mul_shift_round(num, emax, 10), den) + 1;  // +1 LSB: leave the surface
    } else {
      dir = fallback;
    }
    if (delta > emax) delta = emax;
    p = fx::add(p, along(dir, fx::sat_i32(delta)));
  }
  return p;
}

namespace {

// Deformed primitives (§5.2): Newton in the undeformed frame (identity axes,
// centre 0), from D^-1(p) to just outside the undeformed surface, then that
// point mapped forward. It lands on the deformed surface (D maps surface to
// surface); the move follows the image of the undeformed gradient path, not
// the deformed gradient: an approximation, exact where D is a rotation.
fx::Vec3 push_out_deformed(const PrimitiveFrame& f, fx::Vec3 p, fx::Vec3 fallback, int newton_steps) {
  const fx::Vec3 d = fx::sub(p, f.centre);
  int64_t local[3];
  for (int i = 0; i < 3; ++i) {
    if (f.extent[i] <= 0) return p;
    local[i] = component(d, f.axis[i]);
  }
  DeformTrace trace;
  if (!primitive_undeform(f, local, &trace)) return p;
  for (int i = 0; i < 3; ++i)
    if (trace.undeformed[i] >= f.extent[i] || trace.undeformed[i] <= -int64_t{f.extent[i]}) return p;
  PrimitiveFrame plain = f;
  plain.deformation = {};
  plain.centre = {0, 0, 0};
  plain.axis[0] = {fx::kUnitOne, 0, 0};
  plain.axis[1] = {0, fx::kUnitOne, 0};
  plain.axis[2] = {0, 0, fx::kUnitOne};
  // Inside the box: each |p0_i| < extent_i fits a Len.
  const fx::Vec3 start{static_cast<int32_t>(trace.undeformed[0]), static_cast<int32_t>(trace.undeformed[1]),
                       static_cast<int32_t>(trace.undeformed[2])};
  const fx::Vec3 local_fallback{fx::sat_i32(component(fallback, f.axis[0])),
                                fx::sat_i32(component(fallback, f.axis[1])),
                                fx::sat_i32(component(fallback, f.axis[2]))};
  const fx::Vec3 out = primitive_push_out(plain, start, local_fallback, newton_steps);
  if (out == start) return p;
  const int64_t moved_in[3] = {out.x, out.y, out.z};
  int64_t moved[3];
  primitive_deform(f, moved_in, moved);
  // World move = axes * (D(p0') - p3): |each| < 2^40, no overflow.
  int64_t world[3] = {0, 0, 0};
  for (int i = 0; i < 3; ++i) {
    const int64_t delta = moved[i] - local[i];
    world[0] += fx::mul_shift_round(f.axis[i].x, delta, fx::kUnitFracBits);
    world[1] += fx::mul_shift_round(f.axis[i].y, delta, fx::kUnitFracBits);
    world[2] += fx::mul_shift_round(f.axis[i].z, delta, fx::kUnitFracBits);
  }
  return {fx::sat_i32(p.x + world[0]), fx::sat_i32(p.y + world[1]), fx::sat_i32(p.z + world[2])};
}

}  // namespace
}  // namespace sinew::muscle
