#include "joint_anatomy.hpp"

#include <algorithm>
#include <cmath>

namespace sinew::anatomy_build {
namespace {

using layers::RestFrame;
using layers::RigGeometry;

// The belly of the built-in arm's biceps (anatomy_spec's arm), in units of
// its bone radius (1.2 cm): the widest slice's half-width, and its
// thickness over its width (§4.2: "larger across (in X) than in thickness").
constexpr double kBellyHalfWidth = 1.83;
constexpr double kThicknessRatio = 1.33 / 1.83;

// The default slice profile of anatomically-based-modeling §4.2, in model
// units. The end slices are as wide as the lines between the two origins
// and the two insertions; the inner slices widen to a fusiform belly (the
// spindle 4t(1 - t) above the straight line between the end widths,
// t = k / 7, so the widest slices are the middle ones; + - x / only, as the
// whole builder, for bit-identical models); every slice is kThicknessRatio as
// thick as wide. The inner centres move outward (-Y) by how much thicker
// each slice is than the straight line between the end thicknesses, so the
// bone-side face runs straight from end to end and only the outer face
// bulges ("displaced in the negative Y direction ... to compensate for the
// greater thickness of the muscle near its center").
void fusiform_slices(double origin_width, double insertion_width, double belly_half_width, MuscleSpec* s) {
  const double end0 = 0.5 * origin_width, end7 = 0.5 * insertion_width;
  const double belly = std::max({belly_half_width, end0, end7});
  for (size_t k = 0; k < 8; ++k) {
    const double t = static_cast<double>(k) / 7.0;
    const double line = end0 + (end7 - end0) * t;
    const double width = line + (belly - line) * 4 * t * (1 - t);
    s->half_width[k] = width;
    s->half_thickness[k] = kThicknessRatio * width;
    s->bulge[k] = kThicknessRatio * (width - line);
  }
}

struct Box {  // a bone's box in its joint's frame (local units)
  Vec3d axis, side, third;
  double length = 0, radius = 0;  // local units
  double model_radius = 0;        // model units
};

Box box_of(const RigGeometry& g, size_t j, double fallback_radius) {
  const RestFrame& f = g.frame[j];
  Box b;
  const Vec3d along = layers::scaled(g.bone_dir[j], g.bone_length[j] > 0 ? g.bone_length[j] : fallback_radius);
  const Vec3d local_along = layers::sub(layers::to_local(f, layers::add(f.t, along)), {0, 0, 0});
  b.axis = layers::normalized(local_along);
  b.length = layers::norm(local_along);
  const Vec3d side_model = layers::perpendicular(g.bone_dir[j]);
  Vec3d side = layers::dir_to_local(f, side_model);
  side = layers::normalized(layers::sub(side, layers::scaled(b.axis, layers::dot(side, b.axis))));
  b.side = side;
  b.third = layers::cross(b.axis, b.side);
  b.model_radius = 0.27 * (g.skin_radius[j] > 0 ? g.skin_radius[j] : fallback_radius);
  b.radius = b.model_radius * layers::norm(layers::sub(layers::to_local(f, layers::add(f.t, side_model)), {0, 0, 0}));
  return b;
}

// A model-space point as bone-size parameters of joint j's box.
BoneAttachment attach(const RigGeometry& g, const Box& b, int j, const Vec3d& p) {
  const Vec3d local = layers::to_local(g.frame[static_cast<size_t>(j)], p);
  return {j,
          {layers::dot(local, b.axis) / b.length, layers::dot(local, b.side) / b.radius,
           layers::dot(local, b.third) / b.radius}};
}

}  // namespace

bool joint_anatomy(const rigc::RigSpec& rig, const RigGeometry& g, const std::vector<MuscleRequest>& requests,
                   const SkinRequest& skin, AnatomySpec* out, std::vector<MusclePath>* paths, std::string* error) {
  paths->clear();
  const size_t nj = rig.joints.size();
  double mean_radius = 0;
  int radii = 0;
  for (double r : g.skin_radius)
    if (r > 0) mean_radius += r, ++radii;
  if (radii == 0) return *error = "anatomy: no skin vertex is weighted to any joint", false;
  mean_radius /= radii;
  AnatomySpec a;
  std::vector<Box> boxes;
  for (size_t j = 0; j < nj; ++j) {
    boxes.push_back(box_of(g, j, mean_radius));
    const Box& b = boxes.back();
    if (!(b.length > 0) || !(b.radius > 0))
      return *error = "anatomy: joint '" + rig.joints[j].name + "' has a degenerate bone", false;
    a.bones.push_back({b.length, b.radius, b.axis, b.side});
  }
  for (size_t i = 0; i < requests.size(); ++i) {
    const MuscleRequest& m = requests[i];
    const std::string name = "muscle '" + m.name + "'";
    if (m.origin < 0 || m.insertion < 0 || static_cast<size_t>(m.origin) >= nj ||
        static_cast<size_t>(m.insertion) >= nj)
      return *error = name + ": origin or insertion is not a joint of the rig", false;
    if (!layers::is_ancestor_or_self(rig, m.origin, m.insertion))
      return *error = name + ": the origin bone must be the insertion bone or one of its ancestors", false;
    if (!(m.thickness > 0)) return *error = name + ": thickness must be > 0", false;
    const size_t o = static_cast<size_t>(m.origin), ins = static_cast<size_t>(m.insertion);
    const Vec3d uo = g.bone_dir[o], ui = g.bone_dir[ins];
    // The belly's side: given, or the inner side of the insertion joint's bend.
    Vec3d side = m.side;
    if (!(layers::norm(side) > 0) && o != ins && !rig.joints[ins].dofs.empty() &&
        rig.joints[ins].dof_kind == rigc::DofKind::kRotation)
      side = layers::cross(layers::dir_to_model(g.frame[ins], rig.joints[ins].dofs[0].axis), uo);
    side = layers::sub(side, layers::scaled(uo, layers::dot(side, uo)));
    if (!(layers::norm(side) > 1e-9)) side = layers::perpendicular(uo);
    side = layers::normalized(side);
    const Vec3d across_o = layers::cross(uo, side);
    Vec3d side_i = layers::normalized(layers::sub(side, layers::scaled(ui, layers::dot(side, ui))));
    if (!(layers::norm(side_i) > 0)) side_i = layers::perpendicular(ui);
    const Vec3d across_i = layers::cross(ui, side_i);
    const double ro = boxes[o].model_radius, ri = boxes[ins].model_radius;
    const double lo = g.bone_length[o], li = g.bone_length[ins];
    const Vec3d jo = g.frame[o].t, ji = g.frame[ins].t;
    MuscleSpec s;
    s.name = m.name;
    const Vec3d o0 = layers::add(jo, layers::scaled(uo, 0.1 * lo));
    const Vec3d i0 =
        o == ins ? layers::add(jo, layers::scaled(uo, 0.85 * lo)) : layers::add(ji, layers::scaled(ui, 0.35 * li));
    const double r_ins = o == ins ? ro : ri;
    const Vec3d s_ins = o == ins ? side : side_i, a_ins = o == ins ? across_o : across_i;
    // As the arm's biceps: origin[0] and insertion[0] on the -(u x side) edge.
    const Vec3d belly_o = layers::add(o0, layers::scaled(side, 2.0 * ro));
    const Vec3d belly_i = layers::add(i0, layers::scaled(s_ins, 1.2 * r_ins));
    const Vec3d origin_points[2] = {layers::add(belly_o, layers::scaled(across_o, -0.8 * ro)),
                                    layers::add(belly_o, layers::scaled(across_o, 0.8 * ro))};
    const Vec3d insertion_points[2] = {layers::add(belly_i, layers::scaled(a_ins, -0.6 * r_ins)),
                                       layers::add(belly_i, layers::scaled(a_ins, 0.6 * r_ins))};
    for (int k = 0; k < 2; ++k) {
      s.origin[k] = attach(g, boxes[o], m.origin, origin_points[k]);
      s.insertion[k] = attach(g, boxes[ins], m.insertion, insertion_points[k]);
    }
    const double path = layers::norm(layers::sub(i0, o0));
    if (!(path > 0)) return *error = name + ": origin and insertion coincide", false;
    const double cap = 0.15 * path;  // keeps the slices far thinner than the muscle is long
    fusiform_slices(layers::norm(layers::sub(origin_points[1], origin_points[0])),
                    layers::norm(layers::sub(insertion_points[1], insertion_points[0])),
                    std::min(cap, kBellyHalfWidth * ro * m.thickness), &s);
    double widest = 0, thickest = 0;
    for (size_t k = 0; k < 8; ++k) {
      widest = std::max(widest, s.half_width[k]);
      thickest = std::max(thickest, s.half_thickness[k]);
    }
    s.end_axes_from_bones = m.end_axes_from_bones;
    s.slice_edit = m.slice_edit;
    if (m.pivot != 0) {
      // As the arm's biceps: a pivot over the insertion joint, 85 % down the
      // origin bone and 1.8 bone radii out on the belly's side (§4.3: the
      // pivot frame is defined relative to the first origin's segment).
      if (o == ins) return *error = name + ": a pivot needs a muscle that crosses a joint", false;
      s.has_pivot = true;
      s.pivot_variable = m.pivot == 2;
      s.pivot_slice = 6;
      s.pivot = attach(g, boxes[o], m.origin,
                       layers::add(layers::add(jo, layers::scaled(uo, 0.85 * lo)), layers::scaled(side, 1.8 * ro)));
    }
    a.muscles.push_back(s);
    paths->push_back({belly_o, belly_i, widest});
    PrimitiveSpec belly;  // a boxy superellipsoid (p = 4 unless asked) in the belly, as the arm's biceps
    belly.kind = 2;
    belly.attach = 1;
    belly.exponent = m.belly_exponent;
    belly.exponent_z = m.belly_exponent_z;
    belly.index = static_cast<int>(i);
    belly.segment = 3;
    belly.extent = {0.73 * widest, 0.81 * thickest, std::min(0.3 * path, 60 * 0.73 * widest)};
    belly.taper = m.belly_taper;
    belly.twist = m.belly_twist;
    belly.bend = m.belly_bend;
    a.primitives.push_back(belly);
    // A fascia at the belly: the outermost ring vertex (3/4 turn: -Y) of slice 4.
    if (m.band) a.skin.bands.push_back({-1, static_cast<int>(i), 4, 3 * a.ring_vertices / 4, 0.5, {}});
  }
  for (RubberBandSpec b : skin.bands) {
    if (b.ring_vertex < 0) b.ring_vertex = 3 * a.ring_vertices / 4;
    a.skin.bands.push_back(b);
  }
  a.skin.fat_overrides = skin.fat_overrides;
  // Skin: lengths from the skin radius (the arm's 2 cm collision sphere and
  // 6 mm fat at 4.5 cm); every vertex must find an anchor.
  a.skin.iterations = skin.iterations;
  a.skin.warm_start = skin.warm_start;
  a.skin.anchor_coefficient = skin.anchor_coefficient;
  a.skin.solver = skin.solver;
  a.skin.collision_radius = 0.44 * mean_radius;
  a.skin.fat = 0.13 * mean_radius;
  double farthest = 0;
  for (size_t v = 0; v < rig.vertices.size(); ++v) {
    const size_t j = static_cast<size_t>(g.dominant[v]);
    const Vec3d rel = layers::sub(rig.vertices[v].position, g.frame[j].t);
    const double t = std::clamp(layers::dot(rel, g.bone_dir[j]), 0.0, g.bone_length[j]);
    farthest = std::max(farthest, layers::norm(layers::sub(rel, layers::scaled(g.bone_dir[j], t))));
  }
  a.skin.max_anchor_distance = 1.25 * farthest + 1e-6;
  *out = std::move(a);
  return true;
}

}  // namespace sinew::anatomy_build
