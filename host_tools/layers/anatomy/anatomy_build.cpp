#include "anatomy_build.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>

#include "host_tools/layers/common/rig_geometry.hpp"
#include "host_tools/rigc/quantize.hpp"
#include "sim_core/elastic_skin/skin_validate.hpp"
#include "sim_core/elastic_skin/virtual_anchors.hpp"
#include "sim_core/fixed/trig.hpp"
#include "sim_core/muscle/muscle_shape.hpp"
#include "sim_core/muscle/muscle_step.hpp"
#include "sim_core/muscle/muscle_validate.hpp"
#include "sim_core/muscle/primitive_deform.hpp"
#include "sim_core/skeleton/pose.hpp"
#include "trilinear_inverse.hpp"

namespace sinew::anatomy_build {
namespace {

namespace es = elastic_skin;

struct Frame {  // a rest joint transform in double (model units)
  double m[3][3];
  double inv[3][3];
  P3 t;
};

double dot(const P3& a, const P3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
P3 sub(const P3& a, const P3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double norm(const P3& a) { return std::sqrt(dot(a, a)); }
P3 normalized(const P3& a) {
  const double n = norm(a);
  return n > 0 ? P3{a[0] / n, a[1] / n, a[2] / n} : P3{0, 0, 0};
}
P3 apply(const double m[3][3], const P3& v) {
  P3 r;
  for (size_t i = 0; i < 3; ++i) r[i] = m[i][0] * v[0] + m[i][1] * v[1] + m[i][2] * v[2];
  return r;
}

void invert3(const double a[3][3], double out[3][3]) {
  const double c00 = a[1][1] * a[2][2] - a[1][2] * a[2][1], c01 = a[1][2] * a[2][0] - a[1][0] * a[2][2],
               c02 = a[1][0] * a[2][1] - a[1][1] * a[2][0];
  const double det = a[0][0] * c00 + a[0][1] * c01 + a[0][2] * c02;
  const double k = det != 0 ? 1 / det : 0;
  out[0][0] = c00 * k;
  out[1][0] = c01 * k;
  out[2][0] = c02 * k;
  out[0][1] = (a[0][2] * a[2][1] - a[0][1] * a[2][2]) * k;
  out[1][1] = (a[0][0] * a[2][2] - a[0][2] * a[2][0]) * k;
  out[2][1] = (a[0][1] * a[2][0] - a[0][0] * a[2][1]) * k;
  out[0][2] = (a[0][1] * a[1][2] - a[0][2] * a[1][1]) * k;
  out[1][2] = (a[0][2] * a[1][0] - a[0][0] * a[1][2]) * k;
  out[2][2] = (a[0][0] * a[1][1] - a[0][1] * a[1][0]) * k;
}

class Builder {
 public:
  Builder(const rig::Rig& rig, const AnatomySpec& spec, AnatomyModel* out, std::string* error)
      : rig_(rig), spec_(spec), out_(*out), error_(*error), e_(rig.length_exponent) {}

  bool run() {
    const uint32_t joints = rig_.joint_count();
    if (spec_.bones.size() != joints) return fail("anatomy: bones: need one bone size per joint");
    out_ = AnatomyModel{};
    out_.joint_count = joints;
    out_.ring_vertices = static_cast<uint32_t>(spec_.ring_vertices);
    rest_pose();
    return muscles() && primitives() && rest_muscle_state() && check_translations() && anchors() && springs() &&
           bands() && params() && validate_skin() && rest_error();
  }

 private:
  bool fail(const std::string& m) {
    error_ = m;
    return false;
  }
  fx::Len len(double v) const { return rigc::to_len(v, e_); }
  double from_len(int64_t v) const { return std::ldexp(static_cast<double>(v), e_ - 20); }
  P3 from_vec(fx::Vec3 v) const { return {from_len(v.x), from_len(v.y), from_len(v.z)}; }
  static P3 from_unit(fx::Vec3 v) {
    return {std::ldexp(static_cast<double>(v.x), -30), std::ldexp(static_cast<double>(v.y), -30),
            std::ldexp(static_cast<double>(v.z), -30)};
  }
  static fx::Vec3 to_unit(const P3& n) {
    return {rigc::to_fixed(n[0], 30), rigc::to_fixed(n[1], 30), rigc::to_fixed(n[2], 30)};
  }
  fx::Vec3 to_vec(const P3& p) const { return {len(p[0]), len(p[1]), len(p[2])}; }

  // Where a file's bind pose (the inverse of its inverse bind matrices, the
  // space its mesh is in) differs from its nodes' rest pose, the builder
  // works in the bind pose: attachments and anchors are then bind-space
  // joint coordinates, which the runtime maps with model x inverse bind.
  // Rigs whose rest pose is their bind pose (the built-in ones) keep the
  // engine's rest transforms exactly.
  void bind_pose() {
    for (const rig::PaletteRecord& p : rig_.palette) {
      if (p.joint >= rest_model_.size()) continue;
      double a[3][3], inv[3][3], t[3];
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) a[r][c] = std::ldexp(static_cast<double>(p.inverse_bind.m[r][c]), -24);
        t[r] = from_len(p.inverse_bind.t[r]);
      }
      invert3(a, inv);
      fx::Mat34 bind{};
      double difference = 0;
      const fx::Mat34& rest = rest_model_[p.joint];
      for (int r = 0; r < 3; ++r) {
        const double tr = -(inv[r][0] * t[0] + inv[r][1] * t[1] + inv[r][2] * t[2]);
        for (int c = 0; c < 3; ++c) {
          bind.m[r][c] = rigc::to_fixed(inv[r][c], 24);
          difference = std::max(difference, std::fabs(inv[r][c] - std::ldexp(static_cast<double>(rest.m[r][c]), -24)));
        }
        bind.t[r] = len(tr);
        difference = std::max(difference, std::fabs(tr - from_len(rest.t[r])) / std::ldexp(1.0, e_));
      }
      if (difference > 1e-4) rest_model_[p.joint] = bind;
    }
  }

  void rest_pose() {
    const uint32_t joints = rig_.joint_count();
    std::vector<skeleton::LocalPose> locals(joints);
    rest_model_.assign(joints, fx::Mat34{});
    skeleton::rest_locals(rig_, locals);
    skeleton::locals_to_model(rig_, locals, rest_model_);
    bind_pose();
    frames_.resize(joints);
    for (uint32_t j = 0; j < joints; ++j) {
      Frame& f = frames_[j];
      for (int r = 0; r < 3; ++r) {
        for (int c = 0; c < 3; ++c) f.m[r][c] = std::ldexp(static_cast<double>(rest_model_[j].m[r][c]), -24);
        f.t[static_cast<size_t>(r)] = from_len(rest_model_[j].t[r]);
      }
      invert3(f.m, f.inv);
    }
  }

  fx::Vec3 bone_point(const BoneAttachment& a) const {
    const BoneSize& b = spec_.bones[static_cast<size_t>(a.bone)];
    const P3 third{b.axis[1] * b.side[2] - b.axis[2] * b.side[1], b.axis[2] * b.side[0] - b.axis[0] * b.side[2],
                   b.axis[0] * b.side[1] - b.axis[1] * b.side[0]};
    P3 local;
    for (size_t i = 0; i < 3; ++i)
      local[i] =
          a.param[0] * b.length * b.axis[i] + a.param[1] * b.radius * b.side[i] + a.param[2] * b.radius * third[i];
    return to_vec(local);
  }
  // Outward unit normal of a bone's surface at an attachment (§4.2), in the
  // joint frame: the bone is the capsule of radius b.radius around the
  // segment 0..length along b.axis, so the normal is the direction from the
  // nearest point of that segment. Zero when the point is on the segment.
  P3 bone_normal(const BoneAttachment& a) const {
    const BoneSize& b = spec_.bones[static_cast<size_t>(a.bone)];
    const P3 third{b.axis[1] * b.side[2] - b.axis[2] * b.side[1], b.axis[2] * b.side[0] - b.axis[0] * b.side[2],
                   b.axis[0] * b.side[1] - b.axis[1] * b.side[0]};
    const double along = (a.param[0] - std::clamp(a.param[0], 0.0, 1.0)) * b.length;
    P3 q;
    for (size_t i = 0; i < 3; ++i)
      q[i] = along * b.axis[i] + a.param[1] * b.radius * b.side[i] + a.param[2] * b.radius * third[i];
    return normalized(q);
  }

  // Table 1 rotation R = Rz Ry Rx (degrees) as its columns: the rotated
  // X, Y, Z axes in the default slice frame.
  static void rotation_columns(const Vec3d& deg, fx::Vec3 axis[3]) {
    // Sines and cosines from sim_core's fixed-point table (libm's may
    // differ between platforms; these are exact Q2.30 values everywhere).
    double c[3], sn[3];
    for (size_t i = 0; i < 3; ++i) {
      const fx::SinCos t = fx::sin_cos(static_cast<fx::Angle>(rigc::to_angle(deg[i])));
      c[i] = std::ldexp(static_cast<double>(t.cos), -30);
      sn[i] = std::ldexp(static_cast<double>(t.sin), -30);
    }
    const double cx = c[0], sx = sn[0], cy = c[1], sy = sn[1], cz = c[2], sz = sn[2];
    const double r[3][3] = {{cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx},
                            {sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx},
                            {-sy, cy * sx, cy * cx}};
    for (size_t col = 0; col < 3; ++col) axis[col] = to_unit({r[0][col], r[1][col], r[2][col]});
  }

  bool shape(const MuscleSpec& s, const std::string& where, muscle::MuscleShape* out) const {
    if (s.pivot_variable && !s.has_pivot) return fail_c(where + "pivot = \"variable\" needs a pivot");
    out->pivot_mode = static_cast<uint8_t>(s.pivot_variable ? muscle::PivotMode::kVariable : muscle::PivotMode::kFixed);
    if (s.end_axes_from_bones) {
      out->end_axes = static_cast<uint8_t>(muscle::EndAxes::kBoneNormals);
      const BoneAttachment* at[4] = {&s.origin[0], &s.origin[1], &s.insertion[0], &s.insertion[1]};
      for (size_t k = 0; k < 4; ++k) {
        const P3 n = bone_normal(*at[k]);
        if (!(norm(n) > 0.5)) return fail_c(where + "an attachment lies on its bone's axis: no surface normal (§4.2)");
        out->end_normal[k] = to_unit(n);
      }
    }
    for (size_t k = 0; k < muscle::kSlices; ++k) {
      const SliceEditSpec& e = s.slice_edit[k];
      const bool end = k == 0 || k + 1 == muscle::kSlices;
      for (size_t c = 0; c < 3; ++c)
        if (!(std::fabs(e.rotate[c]) <= 90))
          return fail_c(where + "slice " + std::to_string(k) + " rotate must be within [-90, 90] degrees");
      if (end &&
          (e.translate[0] != 0 || e.translate[1] != 0 || e.translate[2] != 0 || e.rotate[1] != 0 || e.rotate[2] != 0))
        return fail_c(where + "slice " + std::to_string(k) +
                      ": end slices cannot be translated and turn about X only (§4.3)");
      out->slice[k].translate = to_vec(e.translate);
      if (e.rotate[0] != 0 || e.rotate[1] != 0 || e.rotate[2] != 0) rotation_columns(e.rotate, out->slice[k].axis);
    }
    return true;
  }
  bool fail_c(const std::string& m) const {
    error_ = m;
    return false;
  }

  bool bone_ok(int bone) const { return bone >= 0 && static_cast<uint32_t>(bone) < rig_.joint_count(); }

  bool muscles() {
    for (size_t i = 0; i < spec_.muscles.size(); ++i) {
      const MuscleSpec& s = spec_.muscles[i];
      const std::string where = "muscle " + std::to_string(i) + " (" + s.name + "): ";
      muscle::MuscleRecord r;
      for (int k = 0; k < 2; ++k) {
        if (!bone_ok(s.origin[k].bone) || !bone_ok(s.insertion[k].bone))
          return fail(where + "origin/insertion bone is not a joint of the rig");
        r.origin[k] = {static_cast<uint32_t>(s.origin[k].bone), bone_point(s.origin[k])};
        r.insertion[k] = {static_cast<uint32_t>(s.insertion[k].bone), bone_point(s.insertion[k])};
      }
      if (s.has_pivot) {
        if (!bone_ok(s.pivot.bone)) return fail(where + "pivot bone is not a joint of the rig");
        r.pivot_bone = s.pivot.bone;
        r.pivot_slice = static_cast<uint32_t>(s.pivot_slice);
        r.pivot_local = bone_point(s.pivot);
      }
      for (size_t k = 0; k < muscle::kSlices; ++k) {
        r.half_width[k] = len(s.half_width[k]);
        r.half_thickness[k] = len(s.half_thickness[k]);
        r.bulge[k] = len(s.bulge[k]);
      }
      r.rest_length = 1;  // measured below with the runtime's own arithmetic
      out_.muscles.push_back(r);
      muscle::MuscleShape sh;
      if (!shape(s, where, &sh)) return false;
      out_.shapes.push_back(sh);
    }
    bool shaped = false;
    for (const muscle::MuscleShape& sh : out_.shapes) shaped = shaped || !muscle::is_default_shape(sh);
    if (!shaped) out_.shapes.clear();  // default shapes: the model stays MUSC v1/v2, bit for bit
    return true;
  }

  // |translate| <= the rest length (a slice cannot leave its muscle's reach).
  bool check_translations() {
    for (size_t i = 0; i < out_.shapes.size(); ++i)
      for (size_t k = 0; k < muscle::kSlices; ++k) {
        const SliceEditSpec& e = spec_.muscles[i].slice_edit[k];
        if (norm({e.translate[0], e.translate[1], e.translate[2]}) > from_len(out_.muscles[i].rest_length))
          return fail("muscle " + std::to_string(i) + " (" + spec_.muscles[i].name + "): slice " + std::to_string(k) +
                      " translate is longer than the muscle's rest length");
      }
    return true;
  }

  bool primitives() {
    for (size_t i = 0; i < spec_.primitives.size(); ++i) {
      const PrimitiveSpec& p = spec_.primitives[i];
      muscle::PrimitiveRecord r;
      r.kind = static_cast<uint8_t>(p.kind);
      r.attach = static_cast<uint8_t>(p.attach);
      // Barr's exponents, Q16.16; the validator checks kinds and the record.
      const double across = p.exponent, along = p.exponent_z > 0 ? p.exponent_z : p.exponent;
      if (!(across >= 1 && across <= 16) || !(along >= 1 && along <= 16))
        return fail("primitive " + std::to_string(i) + ": exponent and exponent_z must be within [1, 16]");
      const muscle::PrimitiveExponents e{rigc::to_fixed(across, 16), rigc::to_fixed(along, 16)};
      r.exponent = muscle::record_exponent(e);
      out_.exponents.push_back(e);
      r.active = p.active ? 1 : 0;
      r.index = static_cast<uint32_t>(p.index);
      r.segment = static_cast<uint32_t>(p.segment);
      r.centre = to_vec(p.centre);
      for (size_t c = 0; c < 3; ++c) r.extent[c] = len(p.extent[c]);
      out_.primitives.push_back(r);
      // Degrees -> binary angles (2^32 a turn); the validator checks the ranges.
      const auto angle = [](double deg) { return rigc::to_angle(deg); };
      muscle::PrimitiveDeformation d;
      d.taper = rigc::to_fixed(p.taper, 30);
      d.twist = angle(p.twist);
      d.bend = angle(p.bend);
      out_.deformations.push_back(d);
    }
    bool deformed = false;
    for (const muscle::PrimitiveDeformation& d : out_.deformations) deformed = deformed || muscle::is_deformed(d);
    if (!deformed) out_.deformations.clear();  // none deformed: MUSC v1, bit for bit
    bool general = false;
    for (const muscle::PrimitiveRecord& r : out_.primitives) general = general || r.exponent == 0;
    if (!general) out_.exponents.clear();  // every exponent 2, 4 or 8: MUSC v1-v3, bit for bit
    return true;
  }

  bool step_rest() {
    const muscle::MuscleModel mm = out_.muscle_model();
    muscle_memory_.assign(muscle::muscle_state_bytes(mm) / 8 + 1, 0);
    muscle::LayerStatus st = muscle::muscle_init(mm, muscle_memory_.data(), muscle_memory_.size() * 8, &mstate_);
    if (st.ok()) st = muscle::muscle_step(mm, rest_model_, &mstate_);
    if (!st.ok()) return fail(std::string("anatomy: ") + st.message);
    return true;
  }

  bool rest_muscle_state() {
    const muscle::LayerStatus v = muscle::muscle_validate(out_.muscle_model(), rig_);
    if (!v.ok()) return fail(std::string("anatomy: ") + v.message);
    if (!step_rest()) return false;
    for (size_t i = 0; i < out_.muscles.size(); ++i) {
      if (mstate_.length[i] <= 0) return fail("muscle " + std::to_string(i) + ": zero rest length");
      out_.muscles[i].rest_length = mstate_.length[i];
    }
    return step_rest();  // scale is exactly 1 at rest now
  }

  P3 muscle_vertex(uint32_t m, uint32_t slice, uint32_t j) const {
    const uint32_t at = muscle::muscle_vertex_index(mstate_.ring_vertices, m, slice, j);
    return {from_len(mstate_.vertex[0][at]), from_len(mstate_.vertex[1][at]), from_len(mstate_.vertex[2][at])};
  }

  struct MuscleHit {
    bool found = false;
    uint32_t muscle = 0, segment = 0;
    P3 stu{};
    double distance = std::numeric_limits<double>::infinity();
    double residual = 0;
  };

  // Whether joint j lies on the chain from the muscle's origin bone down to
  // its insertion bone: the bones that move the muscle (§4.2).
  bool on_muscle_chain(uint32_t m, uint32_t j) const {
    const muscle::MuscleRecord& r = out_.muscles[m];
    for (int32_t at = static_cast<int32_t>(r.insertion[0].bone); at >= 0;
         at = rig_.joints[static_cast<uint32_t>(at)].parent) {
      if (static_cast<uint32_t>(at) == j) return true;
      if (static_cast<uint32_t>(at) == r.origin[0].bone) return false;
    }
    return false;
  }

  // A skin vertex rides on a muscle only when the bones its skinning follows
  // are the muscle's own: a muscle near the skin at rest but moved by other
  // bones (a neighbouring finger's flexor) would carry the vertex away from
  // its limb as soon as either moves.
  bool muscle_moves_vertex(uint32_t m, uint32_t v) const {
    uint32_t ja = 0, jb = 0;
    double wb = 0;
    bone_pair(v, &ja, &jb, &wb);
    return on_muscle_chain(m, ja) && (wb <= 0 || on_muscle_chain(m, jb));
  }

  MuscleHit nearest_muscle(const P3& p, uint32_t v) {
    MuscleHit best;
    const uint32_t ring = mstate_.ring_vertices;
    for (uint32_t m = 0; m < out_.muscles.size(); ++m)
      for (uint32_t k = 0; k + 1 < muscle::kSlices; ++k) {
        if (!muscle_moves_vertex(m, v)) break;
        fx::Vec3 cf[8];
        es::muscle_cell(mstate_, m, k, cf);
        P3 corners[8];
        for (int c = 0; c < 8; ++c) corners[c] = from_vec(cf[c]);
        P3 stu;
        double residual = 0;
        if (!trilinear_inverse(corners, p, &stu, &residual) || !(residual < 1e-9)) continue;
        if (!(stu[2] >= 0 && stu[2] <= 1 && std::fabs(stu[0]) <= 15 && std::fabs(stu[1]) <= 15)) continue;
        double d = std::numeric_limits<double>::infinity();
        for (uint32_t side = 0; side < 2; ++side)
          for (uint32_t j = 0; j < ring; ++j) d = std::min(d, norm(sub(p, muscle_vertex(m, k + side, j))));
        if (d < best.distance) best = {true, m, k, stu, d, residual};
      }
    return best;
  }

  double bone_distance(const P3& p) const {
    double best = std::numeric_limits<double>::infinity();
    for (uint32_t j = 0; j < rig_.joint_count(); ++j) {
      const Frame& f = frames_[j];
      const BoneSize& b = spec_.bones[j];
      const P3 along = apply(f.m, b.axis);
      const P3 dir = {along[0] * b.length, along[1] * b.length, along[2] * b.length};
      const P3 rel = sub(p, f.t);
      const double dd = dot(dir, dir);
      double t = dd > 0 ? dot(rel, dir) / dd : 0;
      t = std::clamp(t, 0.0, 1.0);
      const P3 q{rel[0] - t * dir[0], rel[1] - t * dir[1], rel[2] - t * dir[2]};
      best = std::min(best, std::max(0.0, norm(q) - b.radius));
    }
    return best;
  }

  P3 rest_normal(uint32_t v) const {
    if (!rig_.normal[0].empty())
      return normalized(from_unit({rig_.normal[0][v], rig_.normal[1][v], rig_.normal[2][v]}));
    return normalized(face_normals_[v]);
  }

  void face_normals() {
    const uint32_t n = rig_.vertex_count();
    face_normals_.assign(n, P3{0, 0, 0});
    rest_.resize(n);
    for (uint32_t v = 0; v < n; ++v)
      rest_[v] = from_vec({rig_.position[0][v], rig_.position[1][v], rig_.position[2][v]});
    for (size_t t = 0; t + 2 < rig_.triangles.size(); t += 3) {
      const uint32_t a = rig_.triangles[t], b = rig_.triangles[t + 1], c = rig_.triangles[t + 2];
      const P3 e1 = sub(rest_[b], rest_[a]), e2 = sub(rest_[c], rest_[a]);
      const P3 cr{e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
      for (uint32_t i : {a, b, c})
        for (size_t k = 0; k < 3; ++k) face_normals_[i][k] += cr[k];
    }
  }

  // The vertex's two strongest rig influences (weights renormalised).
  void bone_pair(uint32_t v, uint32_t* a, uint32_t* b, double* wb) const {
    const uint32_t k = rig_.influences_per_vertex;
    double w1 = -1, w2 = -1;
    uint32_t j1 = 0, j2 = 0;
    for (uint32_t i = 0; i < k; ++i) {
      const double w = std::ldexp(static_cast<double>(rig_.influence_weight[v * k + i]), -30);
      const uint32_t j = rig_.palette[rig_.influence_palette[v * k + i]].joint;
      if (w > w1) {
        w2 = w1, j2 = j1;
        w1 = w, j1 = j;
      } else if (w > w2) {
        w2 = w, j2 = j;
      }
    }
    *a = j1;
    *b = w2 > 0 ? j2 : j1;
    *wb = w2 > 0 ? w2 / (w1 + w2) : 0;
  }

  bool anchors() {
    face_normals();
    const uint32_t n = rig_.vertex_count();
    out_.anchors.resize(n);
    for (uint32_t v = 0; v < n; ++v) {
      const P3& p = rest_[v];
      const P3 normal = rest_normal(v);
      const MuscleHit hit = nearest_muscle(p, v);
      const double bone = bone_distance(p);
      const double nearest = std::min(bone, hit.distance);
      if (!(nearest <= spec_.skin.max_anchor_distance))
        return fail("skin vertex " + std::to_string(v) + ": anchor outside every component (nearest surface " +
                    std::to_string(nearest) + " away, limit " + std::to_string(spec_.skin.max_anchor_distance) + ")");
      es::Anchor& a = out_.anchors[v];
      if (hit.found && hit.distance < bone) {
        a.kind = static_cast<uint8_t>(es::AnchorKind::kMuscle);
        out_.report.max_newton_residual = std::max(out_.report.max_newton_residual, hit.residual);
        a.component = hit.muscle;
        a.segment = hit.segment;
        for (size_t c = 0; c < 3; ++c) a.param[c] = rigc::to_fixed(hit.stu[c], 24);
        const muscle::SliceFrame& f = mstate_.frames[hit.muscle * muscle::kSlices + hit.segment];
        a.normal_a = to_unit(
            normalized({dot(normal, from_unit(f.x)), dot(normal, from_unit(f.y)), dot(normal, from_unit(f.z))}));
        ++out_.report.muscle_anchors;
      } else {
        uint32_t ja = 0, jb = 0;
        double wb = 0;
        bone_pair(v, &ja, &jb, &wb);
        a.kind = static_cast<uint8_t>(es::AnchorKind::kBone);
        a.component = ja;
        a.bone_b = jb;
        a.weight_b = rigc::to_fixed(wb, 30);
        a.local_a = to_vec(apply(frames_[ja].inv, sub(p, frames_[ja].t)));
        a.local_b = to_vec(apply(frames_[jb].inv, sub(p, frames_[jb].t)));
        a.normal_a = to_unit(normalized(apply(frames_[ja].inv, normal)));
        a.normal_b = to_unit(normalized(apply(frames_[jb].inv, normal)));
        ++out_.report.bone_anchors;
      }
    }
    return true;
  }

  bool springs() {
    struct HalfEdge {
      uint32_t a, b;
      double area;
    };
    std::vector<HalfEdge> list;
    const uint32_t n = rig_.vertex_count();
    std::vector<double> vertex_area(n, 0);
    for (size_t t = 0; t + 2 < rig_.triangles.size(); t += 3) {
      const uint32_t v[3] = {rig_.triangles[t], rig_.triangles[t + 1], rig_.triangles[t + 2]};
      const P3 e1 = sub(rest_[v[1]], rest_[v[0]]), e2 = sub(rest_[v[2]], rest_[v[0]]);
      const P3 cr{e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]};
      const double area = norm(cr) / 2;
      for (int i = 0; i < 3; ++i) {
        const uint32_t a = v[i], b = v[(i + 1) % 3];
        list.push_back({std::min(a, b), std::max(a, b), area});
        vertex_area[a] += area / 3;  // eq. (2): each triangle's area shared by its three vertices
      }
    }
    std::sort(list.begin(), list.end(),
              [](const HalfEdge& x, const HalfEdge& y) { return x.a != y.a ? x.a < y.a : x.b < y.b; });
    double length_sum = 0;
    size_t i = 0;
    while (i < list.size()) {
      size_t j = i;
      double areas = 0;
      while (j < list.size() && list[j].a == list[i].a && list[j].b == list[i].b) areas += list[j++].area;
      const uint32_t a = list[i].a, b = list[i].b;
      const fx::Vec3 d{rig_.position[0][b] - rig_.position[0][a], rig_.position[1][b] - rig_.position[1][a],
                       rig_.position[2][b] - rig_.position[2][a]};
      const uint32_t fixed_len = fx::length(d);
      const double l = from_len(fixed_len);
      length_sum += l;
      if (!(l > 0)) return fail("skin edge " + std::to_string(a) + "-" + std::to_string(b) + ": zero length");
      es::Edge e;
      e.a = a;
      e.b = b;
      e.rest = static_cast<fx::Len>(std::floor(spec_.skin.rest_length_ratio * fixed_len + 0.5));
      e.k = stiffness(areas / (l * l));  // eq. (1): k_e = (a1 + a2) / len^2
      out_.edges.push_back(e);
      i = j;
    }
    const double mean = out_.edges.empty() ? 1 : length_sum / static_cast<double>(out_.edges.size());
    out_.report.mean_edge_length = mean;
    out_.report.edges = static_cast<uint32_t>(out_.edges.size());
    // eq. (2), with areas in units of the mean edge length squared so k_a
    // is dimensionless like k_e.
    for (uint32_t v = 0; v < n; ++v)
      out_.anchor_stiffness.push_back(stiffness(spec_.skin.anchor_coefficient * vertex_area[v] / (mean * mean)));
    out_.fat.assign(n, len(spec_.skin.fat));
    for (const auto& [v, t] : spec_.skin.fat_overrides) {
      if (v < 0 || static_cast<uint32_t>(v) >= n)
        return fail("fat override: vertex " + std::to_string(v) + " out of range");
      out_.fat[static_cast<size_t>(v)] = len(t);
    }
    return true;
  }

  static es::Stiffness stiffness(double k) {
    const double q = std::floor(k * 65536.0 + 0.5);
    if (!(q > 0)) return 0;
    return q >= static_cast<double>(es::kMaxStiffness) ? es::kMaxStiffness : static_cast<es::Stiffness>(q);
  }

  // The first crossing of the ray from skin vertex v along its inward rest
  // normal with muscle m's rest surface (its rings, slice to slice, as
  // triangles; Moller-Trumbore), and the ring vertex nearest it.
  bool attach_by_ray(uint32_t v, uint32_t m, uint32_t* slice, uint32_t* ring_vertex) const {
    const P3 origin = rest_[v], dir = layers::scaled(rest_normal(v), -1.0);
    const uint32_t ring = mstate_.ring_vertices;
    double nearest = std::numeric_limits<double>::infinity();
    for (uint32_t k = 0; k + 1 < muscle::kSlices; ++k)
      for (uint32_t j = 0; j < ring; ++j) {
        const P3 a = muscle_vertex(m, k, j), b = muscle_vertex(m, k, (j + 1) % ring);
        const P3 c = muscle_vertex(m, k + 1, j), d = muscle_vertex(m, k + 1, (j + 1) % ring);
        for (const auto& tri : {std::array<P3, 3>{a, b, c}, std::array<P3, 3>{b, d, c}}) {
          const P3 e1 = sub(tri[1], tri[0]), e2 = sub(tri[2], tri[0]);
          const P3 pv = layers::cross(dir, e2);
          const double det = dot(e1, pv);
          if (std::fabs(det) < 1e-18) continue;
          const P3 tv = sub(origin, tri[0]);
          const double u = dot(tv, pv) / det;
          const P3 qv = layers::cross(tv, e1);
          const double w = dot(dir, qv) / det;
          const double t = dot(e2, qv) / det;
          if (u >= 0 && w >= 0 && u + w <= 1 && t >= 0 && t < nearest) nearest = t;
        }
      }
    if (!std::isfinite(nearest)) return false;
    const P3 hit = layers::add(origin, layers::scaled(dir, nearest));
    double best = std::numeric_limits<double>::infinity();
    for (uint32_t k = 0; k < muscle::kSlices; ++k)
      for (uint32_t j = 0; j < ring; ++j) {
        const double dd = norm(sub(muscle_vertex(m, k, j), hit));
        if (dd < best) best = dd, *slice = k, *ring_vertex = j;
      }
    return true;
  }

  bool bands() {
    for (size_t i = 0; i < spec_.skin.bands.size(); ++i) {
      const RubberBandSpec& b = spec_.skin.bands[i];
      const std::string name = b.label.empty() ? "rubber band " + std::to_string(i) : b.label;
      if (b.muscle < 0 || static_cast<size_t>(b.muscle) >= out_.muscles.size() || b.slice < 0 ||
          b.slice >= static_cast<int>(muscle::kSlices) || b.ring_vertex < 0 || b.ring_vertex >= spec_.ring_vertices)
        return fail(name + ": muscle, slice or ring vertex out of range");
      es::RubberBand r;
      r.muscle = static_cast<uint32_t>(b.muscle);
      r.slice = static_cast<uint32_t>(b.slice);
      r.ring_vertex = static_cast<uint32_t>(b.ring_vertex);
      r.k = stiffness(b.stiffness);
      if (b.vertex >= 0) {
        if (static_cast<size_t>(b.vertex) >= rest_.size()) return fail(name + ": skin vertex out of range");
        r.vertex = static_cast<uint32_t>(b.vertex);
      } else {  // the skin point: the vertex nearest the muscle point at rest
        const P3 target = muscle_vertex(r.muscle, r.slice, r.ring_vertex);
        double best = std::numeric_limits<double>::infinity();
        for (uint32_t v = 0; v < rest_.size(); ++v) {
          const double d = norm(sub(rest_[v], target));
          if (d < best) best = d, r.vertex = v;
        }
      }
      // §5.5: the attach point is where the skin point's inward ray meets
      // the muscle; the band pulls to the ring vertex nearest it. A band the
      // builder placed itself (vertex -1) whose ray misses (a skin normal
      // that points past a thin muscle) keeps the muscle point it was
      // selected by; a named skin vertex must meet its muscle.
      if (!attach_by_ray(r.vertex, r.muscle, &r.slice, &r.ring_vertex) && b.vertex >= 0)
        return fail(name + ": the ray from skin vertex " + std::to_string(r.vertex) +
                    " along its inward normal misses muscle " + std::to_string(r.muscle));
      out_.bands.push_back(r);
    }
    out_.report.bands = static_cast<uint32_t>(out_.bands.size());
    return true;
  }

  bool params() {
    const SkinSpec& s = spec_.skin;
    es::SkinParams& p = out_.params;
    p.iterations = static_cast<uint32_t>(std::max(0, s.iterations));
    p.push_back = rigc::to_fixed(s.push_back, 30);
    p.compression_band = rigc::to_fixed(s.compression_band, 30);
    p.collision_radius = len(s.collision_radius);
    p.reaction_gain = rigc::to_fixed(s.reaction_gain, 30);
    p.newton_steps = static_cast<uint32_t>(std::max(0, s.newton_steps));
    p.warm_start = s.warm_start ? 1 : 0;
    // Solver: the runtime measures length in rig units (2^e model units),
    // time in s and mass in kg, so its force unit is kg rig unit / s^2 and a
    // stiffness (force per length) or a damping (force per velocity) has the
    // same number in it as in N/m and N s/m: k x / m and c v / m come out
    // in rig units / s^2 when x and v are in rig units. Accelerations
    // (gravity) scale by 2^-e.
    es::SkinSolverParams& o = out_.solver;
    const SkinSolverSpec& d = s.solver;
    o.mode = static_cast<uint8_t>(d.dynamic ? es::SkinMode::kDynamic : es::SkinMode::kStatic);
    o.tolerance = len(d.tolerance);
    o.fat_thickness = len(d.fat_global);
    o.fat_normal = static_cast<uint8_t>(d.fat_surface_normal ? es::FatNormal::kSurface : es::FatNormal::kAnchor);
    if (d.fat_surface_normal) out_.triangles.assign(rig_.triangles.begin(), rig_.triangles.end());
    if (d.dynamic) {
      Tissue t;
      if (!tissue(d, &t)) return false;
      o.substep_hz = t.substep_hz;
      o.max_substeps = t.max_substeps;
      o.constraint_passes = static_cast<uint32_t>(std::max(0, d.constraint_passes));
      o.vertex_mass = rigc::to_fixed(t.mass, es::kMassFracBits);
      o.stiffness_scale = rigc::to_fixed(t.scale, es::kQ16FracBits);
      o.anchor_damping = rigc::to_fixed(t.anchor_c, es::kQ16FracBits);
      o.band_damping = rigc::to_fixed(t.band_c, es::kQ16FracBits);
      const auto accel = [&](double a) { return rigc::to_fixed(std::ldexp(a, -e_), es::kAccelFracBits); };
      o.gravity = {accel(d.gravity[0]), accel(d.gravity[1]), accel(d.gravity[2])};
      o.edge_damping = rigc::to_fixed(d.edge_damping, es::kQ16FracBits);
      if (d.relaxation) {
        es::SkinSurfaceParams& f = out_.surface;
        f.integrator = static_cast<uint8_t>(es::SkinIntegrator::kRelaxation);
        f.relaxation_iterations = static_cast<uint8_t>(std::clamp(d.relaxation_iterations, 0, 255));
        f.bend = static_cast<es::Stiffness>(rigc::to_fixed(d.bend, es::kStiffnessFracBits));
        // N/m^2 = kg / (m s^2): per rig unit of 2^e m, times 2^e.
        f.pressure = rigc::to_fixed(std::ldexp(d.pressure, e_), es::kQ16FracBits);
        const double reaction = d.reaction_frequency > 0 ? d.reaction_frequency : 10 * d.frequency;
        f.reaction_frequency = rigc::to_fixed(reaction, es::kQ16FracBits);
        if (d.pressure != 0) out_.triangles.assign(rig_.triangles.begin(), rig_.triangles.end());
      }
    }
    return true;
  }

  // The dynamic skin's mass, stiffness and damping, given or derived from the
  // tissue (docs/anatomy.md, "Physical defaults"), and its substep rate.
  struct Tissue {
    double mass = 0, scale = 0, anchor_c = 0, band_c = 0;
    uint32_t substep_hz = 0, max_substeps = 0;
  };
  bool tissue(const SkinSolverSpec& d, Tissue* t) {
    const size_t n = out_.anchor_stiffness.size();
    if (n == 0) return fail("anatomy: the dynamic skin has no vertices");
    double area = 0;  // model units^2 (m^2)
    for (size_t i = 0; i + 2 < rig_.triangles.size(); i += 3) {
      const P3 e1 = sub(rest_[rig_.triangles[i + 1]], rest_[rig_.triangles[i]]);
      const P3 e2 = sub(rest_[rig_.triangles[i + 2]], rest_[rig_.triangles[i]]);
      area += norm({e1[1] * e2[2] - e1[2] * e2[1], e1[2] * e2[0] - e1[0] * e2[2], e1[0] * e2[1] - e1[1] * e2[0]}) / 2;
    }
    double mean_ka = 0;
    for (es::Stiffness k : out_.anchor_stiffness) mean_ka += k / 65536.0;
    mean_ka /= static_cast<double>(n);
    t->mass = d.vertex_mass > 0 ? d.vertex_mass : d.surface_density * area / static_cast<double>(n);
    const double omega = 2 * M_PI * d.frequency;
    if (d.stiffness_scale > 0) {
      t->scale = d.stiffness_scale;
    } else {
      if (!(mean_ka > 0)) return fail("anatomy: the skin's anchors have no stiffness to derive stiffness_scale from");
      t->scale = t->mass * omega * omega / mean_ka;
    }
    t->anchor_c = d.anchor_damping >= 0 ? d.anchor_damping : 2 * d.damping_ratio * t->mass * omega;
    t->band_c = d.band_damping >= 0 ? d.band_damping : t->anchor_c;
    if (!(t->mass >= std::ldexp(1.0, -es::kMassFracBits) && t->mass < 128))
      return fail("anatomy: [skin] vertex mass " + std::to_string(t->mass) + " kg outside [2^-24, 128)");
    // The runtime's stability bound (Gershgorin): omega_max^2 = max over
    // vertices of (k_a + 2 sum k_e + sum k_r) scale / m.
    std::vector<double> row(n, 0);
    for (size_t v = 0; v < n; ++v) row[v] = out_.anchor_stiffness[v] / 65536.0;
    for (const es::Edge& e : out_.edges) row[e.a] += 2 * e.k / 65536.0, row[e.b] += 2 * e.k / 65536.0;
    for (const es::RubberBand& b : out_.bands) row[b.vertex] += b.k / 65536.0;
    const double omega_max = std::sqrt(*std::max_element(row.begin(), row.end()) * t->scale / t->mass);
    if (d.substep_hz > 0) {
      t->substep_hz = static_cast<uint32_t>(d.substep_hz);
      t->max_substeps = static_cast<uint32_t>(std::max(0, d.max_substeps));
      if (!d.relaxation && omega_max > t->substep_hz)
        return fail("anatomy: [skin] substep_hz = " + std::to_string(d.substep_hz) +
                    " is too low for the skin's stiffest mode (omega_max " + std::to_string(omega_max) +
                    " rad/s needs h omega <= 1: at least " + std::to_string(static_cast<long>(std::ceil(omega_max))) +
                    " Hz)");
    } else {
      // The runtime's stability bound h omega_max <= 1 (half symplectic
      // Euler's limit of 2), on a multiple of 1 kHz so that the usual loop
      // rates share the substep. omega_max is the membrane's stiffest mode;
      // the modes one sees, near the anchor frequency, have h omega far
      // smaller (10 Hz at 1 kHz: 0.063, frequency error (h omega)^2/24 <
      // 2e-4).
      t->substep_hz = static_cast<uint32_t>(1000 * std::max(1.0, std::ceil(omega_max / 1000)));
      if (t->substep_hz > es::kMaxSubstepHz) return fail("anatomy: the skin is too stiff for any substep rate");
      t->max_substeps = std::clamp<uint32_t>((t->substep_hz + 99) / 100,
                                             static_cast<uint32_t>(std::max(1, d.max_substeps)), es::kMaxSubsteps);
    }
    out_.report.vertex_mass = t->mass;
    out_.report.stiffness_scale = t->scale;
    out_.report.anchor_damping = t->anchor_c;
    out_.report.omega_max = omega_max;
    out_.report.substep_hz = t->substep_hz;
    return true;
  }

  bool validate_skin() {
    const es::LayerStatus st = es::skin_validate(out_.skin_model(), rig_, out_.muscle_model());
    if (!st.ok()) return fail(std::string("anatomy: ") + st.message);
    return true;
  }

  // Forward map at rest, with the runtime's arithmetic, against the rest skin.
  bool rest_error() {
    double worst = 0;
    for (uint32_t v = 0; v < out_.anchors.size(); ++v) {
      const es::AnchorPoint a = es::map_anchor(out_.anchors[v], rest_model_, mstate_);
      worst = std::max(worst, norm(sub(from_vec(a.position), rest_[v])));
    }
    out_.report.max_rest_anchor_error = worst;
    return true;
  }

  const rig::Rig& rig_;
  const AnatomySpec& spec_;
  AnatomyModel& out_;
  std::string& error_;
  int32_t e_;
  std::vector<fx::Mat34> rest_model_;
  std::vector<Frame> frames_;
  std::vector<uint64_t> muscle_memory_;
  muscle::MuscleState mstate_;
  std::vector<P3> rest_, face_normals_;
};

}  // namespace

bool build_anatomy(const rig::Rig& rig, const AnatomySpec& spec, AnatomyModel* out, std::string* error) {
  return Builder(rig, spec, out, error).run();
}

}  // namespace sinew::anatomy_build
