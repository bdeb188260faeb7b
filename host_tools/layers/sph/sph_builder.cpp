#include "sph_builder.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <numeric>

#include "host_tools/layers/common/rig_geometry.hpp"
#include "host_tools/rigc/builtin_rigs.hpp"
#include "host_tools/rigc/quantize.hpp"
#include "sim_core/engine/engine.hpp"
#include "sim_core/fixed/trig.hpp"
#include "sim_core/sph/sph_grid.hpp"
#include "sim_core/sph/sph_state.hpp"

namespace sinew::layers {
namespace {

using rigc::Vec3d;

// SplitMix64: the same jitter on every platform.
struct Rng {
  uint64_t s;
  double unit() {  // [0, 1), exact
    uint64_t z = (s += 0x9E3779B97F4A7C15u);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9u;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBu;
    z ^= z >> 31;
    return static_cast<double>(z >> 11) * (1.0 / 9007199254740992.0);
  }
};

Vec3d axpy(const Vec3d& p, double s, const Vec3d& d) { return {p[0] + s * d[0], p[1] + s * d[1], p[2] + s * d[2]}; }

// Cube root by Newton's method (no libm cbrt: it differs between platforms).
double cube_root(double v) {
  double x = v > 1 ? v : 1;
  for (int i = 0; i < 200; ++i) x = (2 * x + v / (x * x)) / 3;
  return x;
}

std::vector<Vec3d> joint_positions(const rigc::RigSpec& spec) {
  std::vector<Vec3d> model(spec.joints.size());
  for (size_t j = 0; j < spec.joints.size(); ++j) {
    const rigc::JointSpec& js = spec.joints[j];
    const Vec3d base = js.parent >= 0 ? model[static_cast<size_t>(js.parent)] : Vec3d{0, 0, 0};
    model[j] = {base[0] + js.translation[0], base[1] + js.translation[1], base[2] + js.translation[2]};
  }
  return model;
}

int64_t q30(double v) { return static_cast<int64_t>(std::floor(std::ldexp(v, 30) + 0.5)); }

struct Lattice {
  std::vector<Vec3d> points;
  std::vector<double> axial;  // coordinate along the capsule axis from the joint
};

// Jittered cubic lattice inside the capsule; the deepest `count` points.
Lattice fill_capsule(const Vec3d& c, const Vec3d& u, double half, double radius, double s, double jitter, uint64_t seed,
                     uint32_t count, bool* enough) {
  const Vec3d helper = std::fabs(u[0]) < 0.9 ? Vec3d{1, 0, 0} : Vec3d{0, 1, 0};
  const Vec3d v = normalized(cross(u, helper)), w = cross(u, v);
  Rng rng{seed};
  std::vector<Vec3d> pts;
  std::vector<double> axial, depth;
  const int na = static_cast<int>(std::floor((half + radius) / s)), nr = static_cast<int>(std::floor(radius / s));
  for (int i = -na; i <= na; ++i)
    for (int j = -nr; j <= nr; ++j)
      for (int k = -nr; k <= nr; ++k) {
        const double a = (i + jitter * (2 * rng.unit() - 1)) * s;
        const double b = (j + jitter * (2 * rng.unit() - 1)) * s;
        const double e = (k + jitter * (2 * rng.unit() - 1)) * s;
        const double along = a < -half ? a + half : (a > half ? a - half : 0);
        const double dist = std::sqrt(along * along + b * b + e * e);
        if (dist > radius) continue;
        pts.push_back(axpy(axpy(axpy(c, a, u), b, v), e, w));
        axial.push_back(a);
        depth.push_back(radius - dist);
      }
  *enough = pts.size() >= count;
  std::vector<size_t> order(pts.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(order.begin(), order.end(), [&](size_t x, size_t y) { return depth[x] > depth[y]; });
  if (order.size() > count) order.resize(count);
  std::sort(order.begin(), order.end());
  Lattice out;
  for (size_t o : order) {
    out.points.push_back(pts[o]);
    out.axial.push_back(axial[o]);
  }
  return out;
}

}  // namespace

sph::SphModel SphBuilt::model() const {
  sph::SphModel m;
  m.params = params;
  m.joint = joint;
  for (int a = 0; a < 3; ++a) {
    m.rest_local[a] = rest_local[static_cast<size_t>(a)];
    m.rest_model[a] = rest_model[static_cast<size_t>(a)];
    m.skin_rest[a] = skin_rest[static_cast<size_t>(a)];
  }
  m.bone = bone;
  m.skin_vertex = skin_vertex;
  return m;
}

bool identity_rest(const rigc::RigSpec& spec) {
  for (const rigc::JointSpec& js : spec.joints)
    if (js.rotation != rigc::Quatd{1, 0, 0, 0} || js.scale != Vec3d{1, 1, 1}) return false;
  return true;
}

bool rest_transforms(const rigc::RigSpec& spec, int32_t e, std::vector<fx::Mat34>* out, std::string* error) {
  out->assign(spec.joints.size(), fx::mat34_identity());
  for (size_t j = 0; j < spec.joints.size(); ++j) {
    const rigc::JointSpec& js = spec.joints[j];
    if (identity_rest(spec)) {
      // As the engine composes them: identity linear parts, so translations add exactly.
      for (int a = 0; a < 3; ++a) {
        const int32_t t = rigc::to_len(js.translation[static_cast<size_t>(a)], e);
        (*out)[j].t[a] = js.parent >= 0 ? (*out)[static_cast<size_t>(js.parent)].t[a] + t : t;
      }
      continue;
    }
    // Rest rotations and scales: the engine's own composition of the
    // quantised local transforms (skeleton::locals_to_model at rest).
    const double n = std::sqrt(js.rotation[0] * js.rotation[0] + js.rotation[1] * js.rotation[1] +
                               js.rotation[2] * js.rotation[2] + js.rotation[3] * js.rotation[3]);
    if (!(n > 0)) return *error = "sph builder: joint " + js.name + " has a zero rest rotation", false;
    const fx::Quat q{rigc::to_fixed(js.rotation[0] / n, 30), rigc::to_fixed(js.rotation[1] / n, 30),
                     rigc::to_fixed(js.rotation[2] / n, 30), rigc::to_fixed(js.rotation[3] / n, 30)};
    const fx::Mat34 local = fx::mat34_from_trs(
        {rigc::to_len(js.translation[0], e), rigc::to_len(js.translation[1], e), rigc::to_len(js.translation[2], e)}, q,
        {rigc::to_fixed(js.scale[0], 24), rigc::to_fixed(js.scale[1], 24), rigc::to_fixed(js.scale[2], 24)});
    (*out)[j] = js.parent < 0 ? local : fx::mul((*out)[static_cast<size_t>(js.parent)], local);
  }
  return true;
}

bool build_sph(const rigc::RigSpec& spec, const SphBuildOptions& o, SphBuilt* out, std::string* error) {
  const int prox = o.proximal_index >= 0 ? o.proximal_index : rigc::joint_index(spec, o.proximal_joint);
  const int dist = o.distal_index >= 0 ? o.distal_index : rigc::joint_index(spec, o.distal_joint);
  if (prox >= static_cast<int>(spec.joints.size()) || dist >= static_cast<int>(spec.joints.size()))
    return *error = "sph builder: joint index beyond the rig's joints", false;
  if (prox < 0) return *error = "sph builder: proximal_joint '" + o.proximal_joint + "' is not in the rig", false;
  if (dist < 0) return *error = "sph builder: distal_joint '" + o.distal_joint + "' is not in the rig", false;
  if (spec.joints[static_cast<size_t>(dist)].dofs.empty())
    return *error = "sph builder: distal_joint '" + o.distal_joint + "' has no degree of freedom to flex", false;
  if (o.particle_count == 0) return *error = "sph builder: particle_count must be at least 1", false;
  if (o.particle_count > sph::kMaxParticles)
    return *error = "sph builder: particle_count " + std::to_string(o.particle_count) + " exceeds the maximum 8192",
           false;
  if (!(o.capsule_radius > 0) || !(o.capsule_half_length >= 0) || !(o.kernel_ratio > 0) || !(o.tick_hz > 0) ||
      o.substeps == 0 || !(o.tissue_mass > 0))
    return *error = "sph builder: capsule_radius, kernel_ratio, tick_hz, substeps and tissue_mass must be > 0", false;

  SphBuilt b;
  b.length_exponent = rigc::choose_length_exponent(spec);
  const int32_t e = b.length_exponent;
  // Joint frames: with identity rest rotations the historical exact path
  // (translations add); otherwise the full rest transforms.
  const bool identity = identity_rest(spec);
  RigGeometry geometry;
  if (!identity && !rig_geometry(spec, &geometry, error)) return *error = "sph builder: " + *error, false;
  const std::vector<Vec3d> jp = identity ? joint_positions(spec) : [&] {
    std::vector<Vec3d> t;
    for (const RestFrame& f : geometry.frame) t.push_back(f.t);
    return t;
  }();
  const Vec3d c = jp[static_cast<size_t>(dist)];
  const Vec3d u = normalized({c[0] - jp[static_cast<size_t>(prox)][0], c[1] - jp[static_cast<size_t>(prox)][1],
                              c[2] - jp[static_cast<size_t>(prox)][2]});
  // Spacing: the volume shared equally, shrunk until the lattice holds enough points.
  const double r = o.capsule_radius, half = o.capsule_half_length;
  const double volume = 3.14159265358979323846 * r * r * (2 * half + 4.0 / 3.0 * r);
  double s = cube_root(volume / o.particle_count);
  Lattice lat;
  bool enough = false;
  for (int i = 0; i < 400 && !enough; ++i, s *= 0.99)
    lat = fill_capsule(c, u, half, r, s, o.jitter, o.seed, o.particle_count, &enough);
  if (!enough) return *error = "sph builder: could not place the requested particles", false;
  s /= 0.99;
  b.spacing_metres = s;
  b.h_metres = o.kernel_ratio * s;

  // The general path takes the rest pose from the engine itself: joint
  // transforms and skinned vertices exactly as the runtime has them, so the
  // particles' rest positions agree with the skin whatever the file's bind
  // pose is (particles are placed in the mesh's bind space).
  std::vector<fx::Mat34> engine_rest;
  std::array<std::vector<fx::Len>, 3> skinned_rest;
  if (!identity) {
    std::vector<uint8_t> blob;
    rigc::CompileReport report;
    if (!rigc::compile_rig(spec, &blob, &report, error)) return false;
    std::vector<uint64_t> aligned(blob.size() / 8 + 1), arena, engine_arena;
    std::memcpy(aligned.data(), blob.data(), blob.size());
    const auto* data = reinterpret_cast<const uint8_t*>(aligned.data());
    size_t bytes = 0;
    rig::Rig rig;
    rig::LoadStatus st = rig::rig_validate(data, blob.size(), &bytes);
    arena.assign(bytes / 8 + 1, 0);
    if (st.ok()) st = rig::rig_init(data, blob.size(), arena.data(), arena.size() * 8, &rig);
    if (!st.ok()) return *error = std::string("sph builder: ") + st.message, false;
    engine_arena.assign(engine::engine_arena_bytes(rig) / 8 + 1, 0);
    engine::Engine eng;
    if (!engine::engine_init(rig, engine_arena.data(), engine_arena.size() * 8, &eng))
      return *error = "sph builder: engine init failed", false;
    engine_rest.assign(eng.model.begin(), eng.model.end());
    for (size_t a = 0; a < 3; ++a)
      skinned_rest[a].assign(eng.vertices.position[a].begin(), eng.vertices.position[a].end());
  }

  const uint32_t n = o.particle_count;
  for (uint32_t i = 0; i < n; ++i) {
    const Vec3d& p = lat.points[i];
    const bool distal = lat.axial[i] >= 0;
    const Vec3d& origin = jp[static_cast<size_t>(distal ? dist : prox)];
    b.bone.push_back(static_cast<uint8_t>(distal ? sph::Bone::kDistal : sph::Bone::kProximal));
    const Vec3d local = identity ? Vec3d{p[0] - origin[0], p[1] - origin[1], p[2] - origin[2]}
                                 : to_local(geometry.frame[static_cast<size_t>(distal ? dist : prox)], p);
    const fx::Vec3 local_len{rigc::to_len(local[0], e), rigc::to_len(local[1], e), rigc::to_len(local[2], e)};
    const fx::Vec3 at_rest =
        identity ? fx::Vec3{rigc::to_len(p[0], e), rigc::to_len(p[1], e), rigc::to_len(p[2], e)}
                 : fx::transform_point(engine_rest[static_cast<size_t>(distal ? dist : prox)], local_len);
    b.rest_model[0].push_back(at_rest.x);
    b.rest_model[1].push_back(at_rest.y);
    b.rest_model[2].push_back(at_rest.z);
    b.rest_local[0].push_back(local_len.x);
    b.rest_local[1].push_back(local_len.y);
    b.rest_local[2].push_back(local_len.z);
  }
  // Skin vertices within h of a particle take the particles' displacement.
  const double h2 = b.h_metres * b.h_metres;
  for (size_t v = 0; v < spec.vertices.size(); ++v) {
    const Vec3d& pv = spec.vertices[v].position;
    bool near = false;
    for (uint32_t i = 0; i < n && !near; ++i) {
      const Vec3d d{pv[0] - lat.points[i][0], pv[1] - lat.points[i][1], pv[2] - lat.points[i][2]};
      near = dot(d, d) < h2;
    }
    if (!near) continue;
    b.skin_vertex.push_back(static_cast<uint32_t>(v));
    for (size_t a = 0; a < 3; ++a) b.skin_rest[a].push_back(identity ? rigc::to_len(pv[a], e) : skinned_rest[a][v]);
  }

  const double dt = 1.0 / (o.tick_hz * o.substeps), unit = std::ldexp(1.0, e), mass = o.tissue_mass / n;
  sph::SphParams& p = b.params;
  p.h = rigc::to_len(b.h_metres, e);
  p.substeps = o.substeps;
  p.max_neighbours = o.max_neighbours;
  const auto unit_gain = [](double v) {
    return static_cast<fx::Unit>(std::clamp<int64_t>(q30(v), INT32_MIN, INT32_MAX));
  };
  p.elastic_gain = unit_gain(o.elastic_stiffness * dt * dt);
  p.pressure_gain = unit_gain(o.pressure_stiffness * dt * dt);
  p.viscosity_gain = unit_gain(o.viscosity * dt);
  p.damping = unit_gain(1 - o.damping * dt);
  // a = -sigma lap(c_s) n / (|n| rho_i) (Mueller 2003 eq. 19) in sim_core's
  // normalised sums: 6 sigma h / (m C), C = 315 / (64 pi) (poly6), as rig
  // units per substep^2 (docs/sph.md).
  const double poly6_constant = 315.0 / (64.0 * 3.14159265358979323846);
  p.tension_gain = unit_gain(6 * o.surface_tension * b.h_metres * dt * dt / (mass * poly6_constant * unit));
  p.load_gain = unit_gain(dt * dt / (mass * unit));
  p.yield_count = o.yield_count != 0 ? o.yield_count : std::max<uint32_t>(1, n / 100);
  p.grid_radius = rigc::to_len(half + r + 2 * b.h_metres, e);
  p.tau_f = 1;  // calibrated below
  b.joint.proximal_joint = static_cast<uint32_t>(prox);
  b.joint.distal_joint = static_cast<uint32_t>(dist);
  const Vec3d axis = normalized(spec.joints[static_cast<size_t>(dist)].dofs[0].axis);
  b.joint.axis = {rigc::to_fixed(axis[0], 30), rigc::to_fixed(axis[1], 30), rigc::to_fixed(axis[2], 30)};
  const Vec3d load = identity ? Vec3d{u[0] * o.load_distance, u[1] * o.load_distance, u[2] * o.load_distance}
                              : to_local(geometry.frame[static_cast<size_t>(dist)], axpy(c, o.load_distance, u));
  b.joint.load_point = {rigc::to_len(load[0], e), rigc::to_len(load[1], e), rigc::to_len(load[2], e)};
  if (o.override_h >= 0) p.h = static_cast<fx::Len>(o.override_h);

  // Tresca limit (§5): "the pressure of the maximum bendable angle as the
  // maximum principal stress, no force as the minimum": half the largest
  // density rise of the tissue rigidly flexed to yield_angle, computed with
  // sim_core's own density so that run time sees the same numbers.
  std::vector<fx::Mat34> rest;
  if (identity) {
    if (!rest_transforms(spec, e, &rest, error)) return false;
  } else {
    rest = engine_rest;
  }
  {
    const sph::SphModel m = b.model();
    // Indices come from the spec's own joint and vertex lists; the loader
    // checks them against the compiled rig (sph_validate).
    const sph::LayerStatus st = sph::sph_validate_model(m);
    if (!st.ok()) return *error = st.message, false;
    std::vector<uint64_t> arena(sph::sph_state_bytes(m) / 8 + 1);
    sph::SphState state;
    sph::LayerStatus is = sph::sph_init(m, rest, arena.data(), arena.size() * 8, &state);
    if (!is.ok()) return *error = is.message, false;
    std::vector<fx::Mat34> posed = rest;
    const fx::Angle a = static_cast<fx::Angle>(rigc::to_angle(calibration_angle_deg(spec, dist, o.yield_angle_deg)));
    const fx::Mat34 flex = fx::mat34_from_quat(fx::quat_from_axis_angle(b.joint.axis, a), {0, 0, 0});
    posed[static_cast<size_t>(dist)] = fx::mul(rest[static_cast<size_t>(dist)], flex);
    is = sph::sph_reset(&state, posed);
    if (!is.ok()) return *error = is.message, false;
    const fx::Vec3 centre{posed[static_cast<size_t>(dist)].t[0], posed[static_cast<size_t>(dist)].t[1],
                          posed[static_cast<size_t>(dist)].t[2]};
    sph::build_neighbours(&state, centre);
    sph::compute_density(&state);
    int64_t spread = 0;
    for (uint32_t i = 0; i < n; ++i)
      spread = std::max<int64_t>(spread, int64_t{state.density[i]} - state.rest_density[i]);
    p.tau_f = static_cast<sph::Dens>(
        std::clamp<double>(std::floor(static_cast<double>(spread) / 2.0 * o.yield_scale + 0.5), 0, INT32_MAX));
  }
  if (o.override_tau_f >= 0) p.tau_f = static_cast<sph::Dens>(o.override_tau_f);
  const sph::LayerStatus st = sph::sph_validate_model(b.model());
  if (!st.ok()) return *error = st.message, false;
  *out = std::move(b);
  return true;
}

double calibration_angle_deg(const rigc::RigSpec& spec, int distal_joint, double yield_angle_deg) {
  if (yield_angle_deg > 0) return yield_angle_deg;
  const auto& dofs = spec.joints[static_cast<size_t>(distal_joint)].dofs;
  const double most = dofs.empty() ? 0 : dofs[0].max;
  return most > 0 && most < kMaxCalibrationDeg ? most : kMaxCalibrationDeg;
}

}  // namespace sinew::layers
