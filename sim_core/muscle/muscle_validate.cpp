#include "muscle_validate.hpp"

#include <cstdlib>

#include "primitive_deform.hpp"

namespace sinew::muscle {
namespace {

LayerStatus bad(const char* what, int64_t index, const char* field, const char* problem, int64_t value = 0,
                bool show = false) {
  return layer_fail(LayerError::kBadValue, what, index, field, problem, value, show);
}

// True if `ancestor` is `joint` or one of its parents (parents precede children).
bool is_ancestor_or_self(const rig::Rig& rig, uint32_t ancestor, uint32_t joint) {
  int32_t j = static_cast<int32_t>(joint);
  for (uint32_t guard = 0; j >= 0 && guard <= rig.joint_count(); ++guard) {
    if (static_cast<uint32_t>(j) == ancestor) return true;
    j = rig.joints[static_cast<uint32_t>(j)].parent;
  }
  return false;
}

LayerStatus check_muscle(const rig::Rig& rig, const MuscleRecord& r, uint32_t i) {
  const uint32_t joints = rig.joint_count();
  for (int k = 0; k < 2; ++k) {
    if (r.origin[k].bone >= joints)
      return bad("muscle", i, "origin.bone", "not a joint of the rig", r.origin[k].bone, true);
    if (r.insertion[k].bone >= joints)
      return bad("muscle", i, "insertion.bone", "not a joint of the rig", r.insertion[k].bone, true);
  }
  for (int o = 0; o < 2; ++o)
    for (int n = 0; n < 2; ++n)
      if (!is_ancestor_or_self(rig, r.origin[o].bone, r.insertion[n].bone))
        return bad("muscle", i, "origin.bone",
                   "origin is after the insertion in the hierarchy (must be the insertion bone or an ancestor)",
                   r.origin[o].bone, true);
  if (r.pivot_bone >= 0) {
    if (static_cast<uint32_t>(r.pivot_bone) >= joints)
      return bad("muscle", i, "pivot_bone", "not a joint of the rig", r.pivot_bone, true);
    if (r.pivot_slice < 1 || r.pivot_slice > kSlices - 2)
      return bad("muscle", i, "pivot_slice", "must be an inner slice (1..6)", r.pivot_slice, true);
  } else if (r.pivot_bone != -1) {
    return bad("muscle", i, "pivot_bone", "must be -1 (no pivot) or a joint", r.pivot_bone, true);
  }
  if (r.rest_length <= 0) return bad("muscle", i, "rest_length", "must be > 0", r.rest_length, true);
  for (uint32_t k = 0; k < kSlices; ++k)
    if (r.half_width[k] < 0 || r.half_thickness[k] < 0)
      return bad("muscle", i, "half_width/half_thickness", "negative slice radius", k, true);
  return {};
}

// Barr's exponents (muscle_model.hpp, PrimitiveExponents): [1, 16],
// exactly 2 on spheres and cylinders, and the record's exponent the one the
// pair needs (2, 4 or 8 for an equal pair of those, else 0).
LayerStatus check_exponents(const PrimitiveRecord& p, const PrimitiveExponents& e, uint32_t i) {
  const bool super = p.kind == static_cast<uint8_t>(PrimitiveKind::kSuperellipsoid);
  const int32_t powers[2] = {e.power_xy, e.power_z};
  const char* names[2] = {"power_xy", "power_z"};
  for (int k = 0; k < 2; ++k) {
    if (powers[k] < kMinPower || powers[k] > kMaxPower)
      return bad("exponents", i, names[k], "outside [1, 16] (Q16.16: 65536..1048576)", powers[k], true);
    if (!super && powers[k] != kPowerTwo)
      return bad("exponents", i, names[k], "must be exactly 2 (131072) for spheres and cylinders", powers[k], true);
  }
  if (p.exponent != record_exponent(e))
    return bad("primitive", i, "exponent", "must be the exponents pair's: 2, 4 or 8 for an equal pair of those, else 0",
               p.exponent, true);
  return {};
}

LayerStatus check_primitive(const rig::Rig& rig, const MuscleModel& model, const PrimitiveRecord& p, uint32_t i) {
  if (p.kind > static_cast<uint8_t>(PrimitiveKind::kSuperellipsoid))
    return bad("primitive", i, "kind", "unknown kind", p.kind, true);
  if (p.attach == static_cast<uint8_t>(PrimitiveAttach::kBone)) {
    if (p.index >= rig.joint_count()) return bad("primitive", i, "index", "not a joint of the rig", p.index, true);
  } else if (p.attach == static_cast<uint8_t>(PrimitiveAttach::kMuscle)) {
    if (p.index >= model.muscles.size()) return bad("primitive", i, "index", "no such muscle", p.index, true);
    if (p.segment + 1 >= kSlices) return bad("primitive", i, "segment", "must be 0..6", p.segment, true);
  } else {
    return bad("primitive", i, "attach", "unknown attachment", p.attach, true);
  }
  const bool super = p.kind == static_cast<uint8_t>(PrimitiveKind::kSuperellipsoid);
  if (!model.exponents.empty()) {
    const LayerStatus s = check_exponents(p, model.exponents[i], i);
    if (!s.ok()) return s;
  } else if (super ? (p.exponent != 2 && p.exponent != 4 && p.exponent != 8) : p.exponent != 2) {
    return bad("primitive", i, "exponent", "must be 2, 4 or 8 (2 for spheres and cylinders)", p.exponent, true);
  }
  fx::Len lo = p.extent[0], hi = p.extent[0];
  for (int c = 0; c < 3; ++c) {
    if (p.extent[c] <= 0) return bad("primitive", i, "extent", "must be > 0", p.extent[c], true);
    if (p.extent[c] < lo) lo = p.extent[c];
    if (p.extent[c] > hi) hi = p.extent[c];
  }
  if (int64_t{hi} > int64_t{lo} * kMaxPrimitiveAspect)
    return bad("primitive", i, "extent", "aspect ratio above 64", hi / lo, true);
  if (p.kind == static_cast<uint8_t>(PrimitiveKind::kSphere) && (p.extent[1] != lo || p.extent[2] != lo || hi != lo))
    return bad("primitive", i, "extent", "a sphere needs three equal extents");
  return {};
}

// Barr deformation ranges (muscle_model.hpp): beyond them the fixed-point
// inverse maps lose their bounds (or the bend's centre enters the shape).
LayerStatus check_deformation(const PrimitiveRecord& p, const PrimitiveDeformation& d, uint32_t i) {
  if (d.taper < -kMaxTaper || d.taper > kMaxTaper)
    return bad("primitive", i, "deformation.taper", "outside [-1/2, 1/2] (Q2.30)", d.taper, true);
  if (d.twist < -kMaxTwist || d.twist > kMaxTwist)
    return bad("primitive", i, "deformation.twist", "beyond a quarter turn", d.twist, true);
  if (d.reserved != 0) return bad("primitive", i, "deformation.reserved", "must be 0", d.reserved, true);
  if (d.bend == 0) return {};
  const int64_t bend = d.bend < 0 ? -int64_t{d.bend} : int64_t{d.bend};
  if (bend < kMinBend || bend > kMaxBend)
    return bad("primitive", i, "deformation.bend", "must be 0 or 1/1024..1/4 turn", d.bend, true);
  const int64_t across = p.extent[0] > p.extent[1] ? p.extent[0] : p.extent[1];
  if (bend_radius(p.extent[2], bend) < 4 * across)
    return bad("primitive", i, "deformation.bend", "bend radius below 4 x the cross-section's extent", d.bend, true);
  return {};
}

// A Q2.30 direction whose squared length is within 2^-10 of one.
bool near_unit(fx::Vec3 v) {
  const int64_t sq = fx::round_shift(fx::dot_wide(v, v), fx::kUnitFracBits);
  const int64_t err = sq - fx::kUnitOne;
  return (err < 0 ? -err : err) <= (int64_t{1} << 20);
}

// The shape's ranges (muscle_model.hpp, MuscleShape).
LayerStatus check_shape(const MuscleRecord& r, const MuscleShape& s, uint32_t i) {
  if (s.end_axes > static_cast<uint8_t>(EndAxes::kBoneNormals))
    return bad("muscle", i, "shape.end_axes", "unknown end-axes mode", s.end_axes, true);
  if (s.pivot_mode > static_cast<uint8_t>(PivotMode::kVariable))
    return bad("muscle", i, "shape.pivot_mode", "unknown pivot mode", s.pivot_mode, true);
  if (s.pivot_mode == static_cast<uint8_t>(PivotMode::kVariable) && r.pivot_bone < 0)
    return bad("muscle", i, "shape.pivot_mode", "a variable pivot needs a pivot (pivot_bone >= 0)");
  if (s.reserved[0] != 0 || s.reserved[1] != 0 || s.reserved2 != 0)
    return bad("muscle", i, "shape.reserved", "must be 0");
  for (int k = 0; k < 4 && s.end_axes == static_cast<uint8_t>(EndAxes::kBoneNormals); ++k)
    if (!near_unit(s.end_normal[k]))
      return bad("muscle", i, "shape.end_normal", "bone normals must be unit vectors", k, true);
  for (uint32_t k = 0; k < kSlices; ++k) {
    const SliceEdit& e = s.slice[k];
    for (int c = 0; c < 3; ++c)
      if (!near_unit(e.axis[c])) return bad("muscle", i, "shape.slice.axis", "axes must be unit vectors", k, true);
    for (int a = 0; a < 3; ++a)
      for (int b = a + 1; b < 3; ++b)
        if (std::abs(fx::round_shift(fx::dot_wide(e.axis[a], e.axis[b]), fx::kUnitFracBits)) > (int64_t{1} << 20))
          return bad("muscle", i, "shape.slice.axis", "axes must be orthogonal", k, true);
    const bool end = k == 0 || k == kSlices - 1;
    if (!end) continue;
    if (e.translate.x != 0 || e.translate.y != 0 || e.translate.z != 0)
      return bad("muscle", i, "shape.slice.translate", "end slices cannot be translated", k, true);
    if (e.axis[0].x != fx::kUnitOne || e.axis[0].y != 0 || e.axis[0].z != 0)
      return bad("muscle", i, "shape.slice.axis", "end slices turn about X only", k, true);
  }
  return {};
}

}  // namespace

LayerStatus muscle_validate(const MuscleModel& model, const rig::Rig& rig) {
  if (model.joint_count != rig.joint_count())
    return bad("muscle model", -1, "joint_count", "differs from the rig's joint count", model.joint_count, true);
  const uint32_t ring = model.ring_vertices;
  if (ring < 4 || ring > kMaxRingVertices || ring % 4 != 0)
    return bad("muscle model", -1, "ring_vertices", "must be a multiple of 4 in [4, 64]", ring, true);
  if (model.muscles.size() > kMaxMuscles) return bad("muscle model", -1, "muscles", "more than 256");
  if (model.primitives.size() > kMaxPrimitives) return bad("muscle model", -1, "primitives", "more than 256");
  for (uint32_t i = 0; i < model.muscles.size(); ++i) {
    const LayerStatus s = check_muscle(rig, model.muscles[i], i);
    if (!s.ok()) return s;
  }
  if (!model.shapes.empty() && model.shapes.size() != model.muscles.size())
    return bad("muscle model", -1, "shapes", "must be empty or one per muscle",
               static_cast<int64_t>(model.shapes.size()), true);
  for (uint32_t i = 0; i < model.shapes.size(); ++i) {
    const LayerStatus s = check_shape(model.muscles[i], model.shapes[i], i);
    if (!s.ok()) return s;
  }
  if (!model.deformations.empty() && model.deformations.size() != model.primitives.size())
    return bad("muscle model", -1, "deformations", "must be empty or one per primitive",
               static_cast<int64_t>(model.deformations.size()), true);
  if (!model.exponents.empty() && model.exponents.size() != model.primitives.size())
    return bad("muscle model", -1, "exponents", "must be empty or one per primitive",
               static_cast<int64_t>(model.exponents.size()), true);
  for (uint32_t i = 0; i < model.primitives.size(); ++i) {
    LayerStatus s = check_primitive(rig, model, model.primitives[i], i);
    if (s.ok() && !model.deformations.empty()) s = check_deformation(model.primitives[i], model.deformations[i], i);
    if (!s.ok()) return s;
  }
  return {};
}

}  // namespace sinew::muscle
