#include "muscle_step.hpp"

#include "muscle_shape.hpp"
#include "sim_core/fixed/rsqrt_fast.hpp"
#include "sim_core/fixed/sqrt.hpp"
#include "superquadric.hpp"
#include "vec_ops.hpp"

namespace sinew::muscle {
namespace {

constexpr fx::Vec3 kAxisX{fx::kUnitOne, 0, 0};

// sqrt(rest / present) in Q2.30, the inner-slice scale of §4.4.
fx::Unit volume_scale(int64_t rest, int64_t present) {
  int64_t ratio = present > 0 ? fx::div_round(rest << fx::kUnitFracBits, present) : int64_t{4} << 30;
  ratio = fx::clamp_i64(ratio, int64_t{1} << 28, (int64_t{4} << 30) - (int64_t{1} << 24));
  return fx::sat_i32(fx::isqrt_fast(static_cast<uint64_t>(ratio) << fx::kUnitFracBits));
}

// Present length of the muscle path (rest = model.rest_length): the two
// straight pieces through the pivot, or the straight line.
int64_t path_length(fx::Vec3 from, fx::Vec3 pivot, fx::Vec3 to, bool has_pivot) {
  if (!has_pivot) return fx::length(fx::sub(to, from));
  return int64_t{fx::length(fx::sub(pivot, from))} + fx::length(fx::sub(to, pivot));
}

// The attachment bones' transforms (origin[0], origin[1], insertion[0],
// insertion[1]) and the muscle's shape, when it has a non-default one.
struct ShapeInputs {
  const fx::Mat34* bone[4] = {};
  const MuscleShape* shape = nullptr;
};

void build_muscle(const MuscleRecord& m, uint32_t index, const fx::Vec3 pts[5], const ShapeInputs& in, MuscleState* s) {
  const MuscleShape* shape = in.shape;
  const fx::Vec3 from = midpoint(pts[0], pts[1]);  // origin midpoint: first end-slice centre
  const fx::Vec3 to = midpoint(pts[2], pts[3]);    // insertion midpoint: last end-slice centre
  const fx::Vec3 pivot = pts[4];
  const int64_t last = kSlices - 1;
  bool has_pivot = m.pivot_bone >= 0;
  if (has_pivot && shape != nullptr && shape->pivot_mode == static_cast<uint8_t>(PivotMode::kVariable)) {
    const fx::Vec3 x_a = fx::sub(pts[1], pts[0]), x_b = fx::sub(pts[3], pts[2]);
    fx::Vec3 ua{}, ub{};
    const bool ok = fx::normalize_to_unit(x_a, &ua) && fx::normalize_to_unit(x_b, &ub);
    has_pivot = !ok || pivot_engaged(from, to, pivot, lerp_ratio(ua, ub, m.pivot_slice, last));
  }
  const int64_t present = path_length(from, pivot, to, has_pivot);
  const fx::Unit scale = volume_scale(m.rest_length, present);
  s->length[index] = fx::sat_i32(present);
  s->scale[index] = scale;

  uint32_t& degenerate = s->stats.degenerate;
  const fx::Vec3 z_line = unit_or(fx::sub(to, from), kAxisX, &degenerate);
  const fx::Vec3 z_in = has_pivot ? unit_or(fx::sub(pivot, from), z_line, &degenerate) : z_line;
  const fx::Vec3 z_out = has_pivot ? unit_or(fx::sub(to, pivot), z_line, &degenerate) : z_line;
  // End-frame X axes: the lines between the two origins and the two insertions (§4.2).
  const fx::Vec3 x_from = unit_or(fx::sub(pts[1], pts[0]), any_perpendicular(z_line), &degenerate);
  const fx::Vec3 x_to = unit_or(fx::sub(pts[3], pts[2]), x_from, &degenerate);
  const bool bone_normals = shape != nullptr && shape->end_axes == static_cast<uint8_t>(EndAxes::kBoneNormals);
  const int64_t kp = has_pivot ? int64_t{m.pivot_slice} : 0;
  const uint32_t ring = s->ring_vertices;

  for (uint32_t k = 0; k < kSlices; ++k) {
    SliceFrame f;
    fx::Vec3 z;
    if (!has_pivot) {
      f.centre = lerp_ratio(from, to, k, last);
      z = z_line;
    } else if (k < kp) {
      f.centre = lerp_ratio(from, pivot, k, kp);
      z = z_in;
    } else if (k > kp) {
      f.centre = lerp_ratio(pivot, to, k - kp, last - kp);
      z = z_out;
    } else {  // the pivot slice bisects the two pieces
      f.centre = pivot;
      z = unit_or(fx::add(z_in, z_out), z_line, &degenerate);
    }
    // X interpolated between the end frames, then made perpendicular to Z.
    const fx::Vec3 x_raw = lerp_ratio(x_from, x_to, k, last);
    const int64_t along_z = component(x_raw, z);
    const fx::Vec3 x_perp = fx::sub(x_raw, along(z, fx::sat_i32(along_z)));
    f.z = z;
    f.x = unit_or(x_perp, any_perpendicular(z), &degenerate);
    if (bone_normals && (k == 0 || k == kSlices - 1)) {
      // §4.2: X is the line between the two origins (insertions); Z the mean
      // bone normal there, made perpendicular to it.
      const bool first = k == 0;
      f.x = first ? x_from : x_to;
      const int a = first ? 0 : 2;
      f.z = end_slice_z(*in.bone[a], shape->end_normal[a], *in.bone[a + 1], shape->end_normal[a + 1], !first, f.x, f.z,
                        &degenerate);
    }
    f.y = cross_unit(f.z, f.x);
    const bool end = k == 0 || k == kSlices - 1;
    const fx::Unit sk = end ? fx::kUnitOne : scale;
    f.radius_x = fx::mul_by_unit(m.half_width[k], sk);
    f.radius_y = fx::mul_by_unit(m.half_thickness[k], sk);
    // Intermediate centres move along -Y, outward from the bone (§4.2).
    f.centre = fx::sub(f.centre, along(f.y, fx::mul_by_unit(m.bulge[k], sk)));
    if (shape != nullptr) apply_slice_edit(shape->slice[k], &f, &degenerate);
    s->frames[index * kSlices + k] = f;
    for (uint32_t j = 0; j < ring; ++j) {
      const fx::Vec3 v = fx::add(fx::add(f.centre, along(f.x, fx::mul_by_unit(f.radius_x, s->ring_cos[j]))),
                                 along(f.y, fx::mul_by_unit(f.radius_y, s->ring_sin[j])));
      const uint32_t at = muscle_vertex_index(ring, index, k, j);
      s->vertex[0][at] = v.x;
      s->vertex[1][at] = v.y;
      s->vertex[2][at] = v.z;
    }
  }
}

// Column c of a rigid bone's linear part as a Q2.30 unit vector.
fx::Vec3 bone_axis(const fx::Mat34& b, int c) {
  const int up = fx::kUnitFracBits - fx::kLinFracBits;
  return {fx::sat_i32(int64_t{b.m[0][c]} << up), fx::sat_i32(int64_t{b.m[1][c]} << up),
          fx::sat_i32(int64_t{b.m[2][c]} << up)};
}

// The frame's exponents: the model's pair, or the record's one exponent.
// A general superquadric's derived terms follow its present extents.
void set_exponents(const PrimitiveRecord& p, const PrimitiveExponents* pair, PrimitiveFrame* f) {
  f->superquadric.power_xy = pair != nullptr ? pair->power_xy : int32_t{p.exponent} << 16;
  f->superquadric.power_z = pair != nullptr ? pair->power_z : int32_t{p.exponent} << 16;
  if (is_general_superquadric(*f)) superquadric_prepare(f);
}

PrimitiveFrame place_primitive(const PrimitiveRecord& p, const PrimitiveDeformation& deformation,
                               const PrimitiveExponents* exponents, std::span<const fx::Mat34> bones,
                               const MuscleModel& model, const MuscleState& s) {
  PrimitiveFrame f;
  f.kind = p.kind;
  f.exponent = p.exponent;
  f.active = p.active;
  f.deformation = deformation;
  if (p.attach == static_cast<uint8_t>(PrimitiveAttach::kBone)) {
    const fx::Mat34& b = bones[p.index];
    f.centre = fx::transform_point(b, p.centre);
    for (int c = 0; c < 3; ++c) {
      f.axis[c] = bone_axis(b, c);
      f.extent[c] = p.extent[c];
    }
    set_exponents(p, exponents, &f);
    return f;
  }
  // Muscle attach: the frame of slice `segment`, centred between it and the
  // next slice, extents scaled like the muscle: X and Y by s, Z by 1 / s^2
  // (= present / rest length), so the primitive keeps its volume.
  const SliceFrame& a = s.frames[p.index * kSlices + p.segment];
  const SliceFrame& b = s.frames[p.index * kSlices + p.segment + 1];
  const fx::Vec3 centre = midpoint(a.centre, b.centre);
  f.axis[0] = a.x;
  f.axis[1] = a.y;
  f.axis[2] = a.z;
  f.centre = fx::add(fx::add(fx::add(centre, along(a.x, p.centre.x)), along(a.y, p.centre.y)), along(a.z, p.centre.z));
  const fx::Unit sc = s.scale[p.index];
  f.extent[0] = fx::mul_by_unit(p.extent[0], sc);
  f.extent[1] = fx::mul_by_unit(p.extent[1], sc);
  const int64_t rest = model.muscles[p.index].rest_length;
  f.extent[2] = fx::sat_i32(fx::div_round(int64_t{p.extent[2]} * s.length[p.index], rest));
  if (p.kind == static_cast<uint8_t>(PrimitiveKind::kSphere)) f.extent[1] = f.extent[2] = f.extent[0];
  set_exponents(p, exponents, &f);
  return f;
}

// Indices the step dereferences, checked every step (cheap) so an
// unvalidated model is rejected instead of read out of bounds.
LayerStatus check_indices(const MuscleModel& model, size_t bones) {
  for (uint32_t i = 0; i < model.muscles.size(); ++i) {
    const MuscleRecord& r = model.muscles[i];
    for (int k = 0; k < 2; ++k)
      if (r.origin[k].bone >= bones || r.insertion[k].bone >= bones)
        return layer_fail(LayerError::kBadValue, "muscle", i, "origin/insertion bone", "not a joint of the rig");
    if (r.pivot_bone >= 0 && (static_cast<size_t>(r.pivot_bone) >= bones || r.pivot_slice < 1 || r.pivot_slice > 6))
      return layer_fail(LayerError::kBadValue, "muscle", i, "pivot", "bone not a joint or pivot_slice outside 1..6");
  }
  if (!model.deformations.empty() && model.deformations.size() != model.primitives.size())
    return layer_fail(LayerError::kBadValue, "muscle model", -1, "deformations", "must be empty or one per primitive");
  if (!model.shapes.empty() && model.shapes.size() != model.muscles.size())
    return layer_fail(LayerError::kBadValue, "muscle model", -1, "shapes", "must be empty or one per muscle");
  if (!model.exponents.empty() && model.exponents.size() != model.primitives.size())
    return layer_fail(LayerError::kBadValue, "muscle model", -1, "exponents", "must be empty or one per primitive");
  for (uint32_t p = 0; p < model.primitives.size(); ++p) {
    const PrimitiveRecord& r = model.primitives[p];
    const bool bone = r.attach == static_cast<uint8_t>(PrimitiveAttach::kBone);
    if (bone ? r.index >= bones : (r.index >= model.muscles.size() || r.segment + 1 >= kSlices))
      return layer_fail(LayerError::kBadValue, "primitive", p, "index", "no such bone or muscle segment");
    if (!bone && model.muscles[r.index].rest_length <= 0)
      return layer_fail(LayerError::kBadValue, "muscle", r.index, "rest_length", "must be > 0");
  }
  return {};
}

}  // namespace

LayerStatus muscle_step(const MuscleModel& model, std::span<const fx::Mat34> bones, MuscleState* state) {
  if (state == nullptr) return layer_fail(LayerError::kBadInput, "muscle step", -1, "state", "null");
  if (bones.size() < model.joint_count)
    return layer_fail(LayerError::kBadInput, "muscle step", -1, "bones", "fewer transforms than the model's joints",
                      static_cast<int64_t>(bones.size()), true);
  const size_t m = model.muscles.size();
  if (state->ring_vertices != model.ring_vertices || state->frames.size() != m * kSlices ||
      state->primitives.size() != model.primitives.size())
    return layer_fail(LayerError::kBadInput, "muscle step", -1, "state", "not initialised for this model");
  const LayerStatus indices = check_indices(model, bones.size());
  if (!indices.ok()) return indices;
  state->stats.recomputed = 0;
  state->stats.degenerate = 0;
  for (uint32_t i = 0; i < m; ++i) {
    const MuscleRecord& r = model.muscles[i];
    const BonePoint pts_def[4] = {r.origin[0], r.origin[1], r.insertion[0], r.insertion[1]};
    fx::Vec3 pts[5];
    for (int p = 0; p < 4; ++p) pts[p] = fx::transform_point(bones[pts_def[p].bone], pts_def[p].local);
    pts[4] = r.pivot_bone >= 0 ? fx::transform_point(bones[static_cast<uint32_t>(r.pivot_bone)], r.pivot_local)
                               : fx::Vec3{0, 0, 0};
    bool moved = state->computed[i] == 0;
    for (int p = 0; p < 5; ++p) moved = moved || !(state->last_points[i * 5 + static_cast<uint32_t>(p)] == pts[p]);
    if (!moved) continue;
    for (int p = 0; p < 5; ++p) state->last_points[i * 5 + static_cast<uint32_t>(p)] = pts[p];
    state->computed[i] = 1;
    ShapeInputs in;
    for (int p = 0; p < 4; ++p) in.bone[p] = &bones[pts_def[p].bone];
    in.shape = model.shapes.empty() ? nullptr : &model.shapes[i];
    build_muscle(r, i, pts, in, state);
    ++state->stats.recomputed;
  }
  const bool deformed = !model.deformations.empty();
  const bool paired = !model.exponents.empty();
  for (uint32_t p = 0; p < model.primitives.size(); ++p)
    state->primitives[p] =
        place_primitive(model.primitives[p], deformed ? model.deformations[p] : PrimitiveDeformation{},
                        paired ? &model.exponents[p] : nullptr, bones, model, *state);
  ++state->stats.steps;
  return {};
}

}  // namespace sinew::muscle
