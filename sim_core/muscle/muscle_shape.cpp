#include "muscle_shape.hpp"

#include "vec_ops.hpp"

namespace sinew::muscle {
namespace {

bool same(fx::Vec3 a, fx::Vec3 b) { return a.x == b.x && a.y == b.y && a.z == b.z; }

bool is_identity(const SliceEdit& e) {
  const SliceEdit identity{};
  return same(e.axis[0], identity.axis[0]) && same(e.axis[1], identity.axis[1]) && same(e.axis[2], identity.axis[2]);
}

// a * d.x + b * d.y + c * d.z for unit a, b, c and Q2.30 coefficients d.
fx::Vec3 combine(fx::Vec3 a, fx::Vec3 b, fx::Vec3 c, fx::Vec3 d) {
  const fx::Vec3 pa = along(a, d.x), pb = along(b, d.y), pc = along(c, d.z);
  return {fx::sat_i32(int64_t{pa.x} + pb.x + pc.x), fx::sat_i32(int64_t{pa.y} + pb.y + pc.y),
          fx::sat_i32(int64_t{pa.z} + pb.z + pc.z)};
}

}  // namespace

bool is_default_shape(const MuscleShape& s) {
  if (s.end_axes != 0 || s.pivot_mode != 0 || s.reserved[0] != 0 || s.reserved[1] != 0 || s.reserved2 != 0)
    return false;
  for (const fx::Vec3& n : s.end_normal)
    if (!same(n, fx::Vec3{0, 0, 0})) return false;
  for (const SliceEdit& e : s.slice)
    if (!same(e.translate, fx::Vec3{0, 0, 0}) || !is_identity(e)) return false;
  return true;
}

bool pivot_engaged(fx::Vec3 from, fx::Vec3 to, fx::Vec3 pivot, fx::Vec3 x_raw) {
  fx::Vec3 z{}, x{};
  if (!fx::normalize_to_unit(fx::sub(to, from), &z)) return true;
  const fx::Vec3 x_perp = fx::sub(x_raw, along(z, fx::sat_i32(component(x_raw, z))));
  if (!fx::normalize_to_unit(x_perp, &x)) return true;
  const fx::Vec3 y = cross_unit(z, x);
  return component(fx::sub(pivot, from), y) < 0;
}

fx::Vec3 end_slice_z(const fx::Mat34& bone_a, fx::Vec3 normal_a, const fx::Mat34& bone_b, fx::Vec3 normal_b,
                     bool inward, fx::Vec3 x, fx::Vec3 fallback, uint32_t* degenerate) {
  const fx::Vec3 na = fx::transform_vector(bone_a, normal_a), nb = fx::transform_vector(bone_b, normal_b);
  // The sum has the mean's direction; halves keep it inside int32.
  fx::Vec3 n{fx::sat_i32(fx::round_shift(int64_t{na.x} + nb.x, 1)),
             fx::sat_i32(fx::round_shift(int64_t{na.y} + nb.y, 1)),
             fx::sat_i32(fx::round_shift(int64_t{na.z} + nb.z, 1))};
  if (inward) n = {fx::neg_sat(n.x), fx::neg_sat(n.y), fx::neg_sat(n.z)};
  const fx::Vec3 perp = fx::sub(n, along(x, fx::sat_i32(component(n, x))));
  return unit_or(perp, fallback, degenerate);
}

void apply_slice_edit(const SliceEdit& edit, SliceFrame* f, uint32_t* degenerate) {
  const fx::Vec3 moved = combine(f->x, f->y, f->z, edit.translate);
  f->centre = fx::add(f->centre, moved);
  if (is_identity(edit)) return;
  const fx::Vec3 x = unit_or(combine(f->x, f->y, f->z, edit.axis[0]), f->x, degenerate);
  const fx::Vec3 z = unit_or(combine(f->x, f->y, f->z, edit.axis[2]), f->z, degenerate);
  f->x = x;
  f->z = z;
  f->y = cross_unit(z, x);
}

}  // namespace sinew::muscle
