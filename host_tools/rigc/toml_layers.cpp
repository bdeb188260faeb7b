#include "toml_layers.hpp"

#include <cmath>
#include <cstdint>
#include <initializer_list>
#include <optional>

namespace sinew::rigc {
namespace {

std::string at(const std::string& path, const toml::node* n, const std::string& key) {
  std::string s = path;
  if (n != nullptr) s += ":" + std::to_string(n->source().begin.line);
  return s + ": " + key;
}

// Refuses keys a table does not know (a typo would otherwise fall back to a default).
bool known_keys(const std::string& path, const toml::table& t, const std::string& table,
                std::initializer_list<const char*> keys, std::string* error) {
  for (const auto& [key, node] : t) {
    bool ok = false;
    for (const char* k : keys) ok |= key.str() == k;
    if (!ok) return *error = at(path, &node, table + " " + std::string(key.str())) + ": unknown key", false;
  }
  return true;
}

bool read_number(const std::string& path, const toml::table& t, const std::string& table, const char* key, double* out,
                 std::string* error) {
  const toml::node* n = t.get(key);
  if (n == nullptr) return true;
  const auto v = n->value<double>();
  if (!v || !std::isfinite(*v)) return *error = at(path, n, table + " " + key) + " must be a finite number", false;
  *out = *v;
  return true;
}

template <typename Int>
bool read_int(const std::string& path, const toml::table& t, const std::string& table, const char* key, int64_t lo,
              int64_t hi, Int* out, std::string* error) {
  const toml::node* n = t.get(key);
  if (n == nullptr) return true;
  const auto v = n->value_exact<int64_t>();
  if (!v || *v < lo || *v > hi)
    return *error = at(path, n, table + " " + key) + " must be an integer in [" + std::to_string(lo) + ", " +
                    std::to_string(hi) + "]",
           false;
  *out = static_cast<Int>(*v);
  return true;
}

bool read_string(const std::string& path, const toml::table& t, const std::string& table, const char* key,
                 std::string* out, std::string* error) {
  const toml::node* n = t.get(key);
  if (n == nullptr) return true;
  const auto v = n->value_exact<std::string>();
  if (!v) return *error = at(path, n, table + " " + key) + " must be a string", false;
  *out = *v;
  return true;
}

bool read_bool(const std::string& path, const toml::table& t, const std::string& table, const char* key, bool* out,
               std::string* error) {
  const toml::node* n = t.get(key);
  if (n == nullptr) return true;
  const auto v = n->value_exact<bool>();
  if (!v) return *error = at(path, n, table + " " + key) + " must be true or false", false;
  *out = *v;
  return true;
}

// `joint = "name"` or `joint = 12` (a glTF node index).
bool read_joint(const std::string& path, const toml::table& t, const std::string& table, const char* key,
                layers::JointRef* out, std::string* error) {
  const toml::node* n = t.get(key);
  if (n == nullptr) return *error = at(path, &t, table + " " + key) + " is required", false;
  out->where = at(path, n, table + " " + key);
  if (const auto name = n->value_exact<std::string>()) return out->name = *name, true;
  if (const auto node = n->value_exact<int64_t>(); node && *node >= 0 && *node < (int64_t{1} << 30))
    return out->node = static_cast<int>(*node), true;
  return *error = out->where + " must be a joint name or a glTF node index", false;
}

// `key = [x, y, z]`, three finite numbers.
bool read_vec3(const std::string& path, const toml::table& t, const std::string& table, const char* key, double out[3],
               std::string* error) {
  const toml::node* n = t.get(key);
  if (n == nullptr) return true;
  const toml::array* a = n->as_array();
  bool good = a != nullptr && a->size() == 3;
  for (size_t i = 0; good && i < 3; ++i) {
    const auto v = a->get(i)->value<double>();
    good = v && std::isfinite(*v);
    if (good) out[i] = *v;
  }
  if (!good) return *error = at(path, n, table + " " + key) + " must be an array of 3 numbers", false;
  return true;
}

// A number key's range, checked after reading: the message names the key
// and the range.
bool in_range(const std::string& path, const toml::table& t, const std::string& table, const char* key, bool ok,
              const std::string& range, std::string* error) {
  if (ok) return true;
  return *error = at(path, t.get(key), table + " " + key) + " must be " + range, false;
}

// [[muscle.slice]] inside a [[muscle]]: Table 1's per-slice edits
// (anatomically-based-modeling §4.3), docs/anatomy.md.
bool read_muscle_slices(const std::string& path, const toml::table& e, layers::MuscleTable* x, std::string* error) {
  const toml::node* n = e.get("slice");
  if (n == nullptr) return true;
  const std::string label = "[[muscle.slice]]";
  const toml::array* a = n->as_array();
  if (a == nullptr) return *error = at(path, n, label) + " must be an array of tables", false;
  bool seen[8] = {};
  for (const toml::node& node : *a) {
    const toml::table* t = node.as_table();
    if (t == nullptr) return *error = at(path, &node, label) + " must be a table", false;
    int index = -1;
    double translate[3] = {0, 0, 0}, rotate[3] = {0, 0, 0};
    if (!known_keys(path, *t, label, {"index", "translate", "rotate"}, error) ||
        !read_int(path, *t, label, "index", 0, 7, &index, error) ||
        !read_vec3(path, *t, label, "translate", translate, error) ||
        !read_vec3(path, *t, label, "rotate", rotate, error))
      return false;
    if (index < 0) return *error = at(path, t, label + " index") + " is required (0..7)", false;
    if (seen[index])
      return *error = at(path, t, label + " index") + " names slice " + std::to_string(index) + " twice", false;
    seen[index] = true;
    const bool end = index == 0 || index == 7;
    for (int c = 0; c < 3; ++c)
      if (!in_range(path, *t, label, "rotate", std::fabs(rotate[c]) <= 90, "within [-90, 90] degrees per axis", error))
        return false;
    if (!in_range(path, *t, label, "translate", !end || (translate[0] == 0 && translate[1] == 0 && translate[2] == 0),
                  "[0, 0, 0] for an end slice (index 0 or 7): only inner slices move (§4.3)", error) ||
        !in_range(path, *t, label, "rotate", !end || (rotate[1] == 0 && rotate[2] == 0),
                  "[x, 0, 0] for an end slice (index 0 or 7): end slices turn about X only (§4.3)", error))
      return false;
    anatomy_build::SliceEditSpec& s = x->slice_edit[static_cast<size_t>(index)];
    s.translate = {translate[0], translate[1], translate[2]};
    s.rotate = {rotate[0], rotate[1], rotate[2]};
  }
  return true;
}

// The [[muscle]] shape keys: end_axes, pivot, the belly's Barr
// deformations and superquadric exponents (ranges of muscle_model.hpp,
// PrimitiveDeformation and PrimitiveExponents).
bool read_muscle_shape(const std::string& path, const toml::table& e, const std::string& n, layers::MuscleTable* x,
                       std::string* error) {
  std::string end_axes = "bone_normals", pivot = "off";
  if (!read_string(path, e, n, "end_axes", &end_axes, error) || !read_string(path, e, n, "pivot", &pivot, error) ||
      !read_number(path, e, n, "belly_taper", &x->belly_taper, error) ||
      !read_number(path, e, n, "belly_twist", &x->belly_twist, error) ||
      !read_number(path, e, n, "belly_bend", &x->belly_bend, error) ||
      !read_number(path, e, n, "belly_exponent", &x->belly_exponent, error))
    return false;
  const bool has_z = e.get("belly_exponent_z") != nullptr;
  if (has_z && !read_number(path, e, n, "belly_exponent_z", &x->belly_exponent_z, error)) return false;
  if (!in_range(path, e, n, "end_axes", end_axes == "path" || end_axes == "bone_normals",
                "\"path\" or \"bone_normals\"", error) ||
      !in_range(path, e, n, "pivot", pivot == "off" || pivot == "on" || pivot == "variable",
                "\"off\", \"on\" or \"variable\"", error) ||
      !in_range(path, e, n, "belly_taper", std::fabs(x->belly_taper) <= 0.5, "within [-0.5, 0.5]", error) ||
      !in_range(path, e, n, "belly_twist", std::fabs(x->belly_twist) <= 90, "within [-90, 90] degrees", error) ||
      !in_range(path, e, n, "belly_bend",
                x->belly_bend == 0 || (std::fabs(x->belly_bend) >= 360.0 / 1024 && std::fabs(x->belly_bend) <= 90),
                "0 or of magnitude within [0.3515625, 90] degrees", error) ||
      !in_range(path, e, n, "belly_exponent", x->belly_exponent >= 1 && x->belly_exponent <= 16, "within [1, 16]",
                error) ||
      !in_range(path, e, n, "belly_exponent_z", !has_z || (x->belly_exponent_z >= 1 && x->belly_exponent_z <= 16),
                "within [1, 16]", error))
    return false;
  x->end_axes_from_bones = end_axes == "bone_normals";
  x->pivot = pivot == "off" ? 0 : pivot == "on" ? 1 : 2;
  return read_muscle_slices(path, e, x, error);
}

const toml::table* table_of(const toml::node& n) { return n.as_table(); }

// [[metaballs.<name>]] inside the [metaballs] table: each an array of tables.
template <typename Read>
bool each_in(const std::string& path, const toml::table& t, const char* name, Read&& read, std::string* error) {
  const toml::node* n = t.get(name);
  if (n == nullptr) return true;
  const std::string label = std::string("[[metaballs.") + name + "]]";
  const toml::array* a = n->as_array();
  if (a == nullptr) return *error = at(path, n, label) + " must be an array of tables", false;
  for (const toml::node& e : *a) {
    const toml::table* tt = e.as_table();
    if (tt == nullptr) return *error = at(path, &e, label) + " must be a table", false;
    if (!read(*tt, label)) return false;
  }
  return true;
}

// The [metaballs] table (docs/metaballs.md, "TOML keys"); the builder checks
// the ranges (metaballs_build::check_options).
bool read_metaballs(const std::string& path, const toml::table& e, layers::MetaballsTable* out, std::string* error) {
  metaballs_build::Options& o = out->options;
  const std::string n = "[metaballs]";
  if (!known_keys(path, e, n,
                  {"ball_spacing", "pbd_iterations", "stretch_stiffness", "jiggle_damping", "jiggle_stretch_stiffness",
                   "jiggle_frequency", "jiggle_window", "overlap_reach", "smoothing_passes", "smoothing_rate",
                   "joint_inner", "joint_outer", "jiggle", "bulge", "action_line"},
                  error) ||
      !read_number(path, e, n, "ball_spacing", &out->ball_spacing, error) ||
      !read_int(path, e, n, "pbd_iterations", 0, 16, &o.pbd_iterations, error) ||
      !read_number(path, e, n, "stretch_stiffness", &o.stretch_stiffness, error) ||
      !read_number(path, e, n, "jiggle_damping", &o.jiggle_damping, error) ||
      !read_number(path, e, n, "jiggle_stretch_stiffness", &o.jiggle_stretch_stiffness, error) ||
      !read_number(path, e, n, "jiggle_frequency", &o.jiggle_frequency, error) ||
      !read_number(path, e, n, "jiggle_window", &o.jiggle_window, error) ||
      !read_number(path, e, n, "overlap_reach", &o.overlap_reach, error) ||
      !read_int(path, e, n, "smoothing_passes", 0, 8, &o.smoothing_passes, error) ||
      !read_number(path, e, n, "smoothing_rate", &o.smoothing_rate, error) ||
      !read_number(path, e, n, "joint_inner", &o.joint_inner, error) ||
      !read_number(path, e, n, "joint_outer", &o.joint_outer, error))
    return false;
  const auto jiggle = [&](const toml::table& t, const std::string& label) {
    metaballs_build::JiggleRegion r;
    if (!known_keys(path, t, label, {"bone", "from", "to", "stiffness"}, error) ||
        !read_string(path, t, label, "bone", &r.bone, error) || !read_number(path, t, label, "from", &r.from, error) ||
        !read_number(path, t, label, "to", &r.to, error) ||
        !read_number(path, t, label, "stiffness", &r.stiffness, error))
      return false;
    o.jiggle.push_back(r);
    return true;
  };
  const auto bulge = [&](const toml::table& t, const std::string& label) {
    metaballs_build::BulgeRegion r;
    if (!known_keys(path, t, label, {"bone", "from", "to", "angle_a", "angle_b", "gain"}, error) ||
        !read_string(path, t, label, "bone", &r.bone, error) || !read_number(path, t, label, "from", &r.from, error) ||
        !read_number(path, t, label, "to", &r.to, error) ||
        !read_string(path, t, label, "angle_a", &r.angle_a, error) ||
        !read_string(path, t, label, "angle_b", &r.angle_b, error) ||
        !read_number(path, t, label, "gain", &r.gain, error))
      return false;
    o.bulge.push_back(r);
    return true;
  };
  const auto action_line = [&](const toml::table& t, const std::string& label) {
    metaballs_build::ActionLineSpec l;
    if (!known_keys(path, t, label, {"origin", "origin_at", "insertion", "insertion_at", "side", "reach", "stiffness"},
                    error) ||
        !read_string(path, t, label, "origin", &l.origin, error) ||
        !read_number(path, t, label, "origin_at", &l.origin_at, error) ||
        !read_string(path, t, label, "insertion", &l.insertion, error) ||
        !read_number(path, t, label, "insertion_at", &l.insertion_at, error) ||
        !read_number(path, t, label, "reach", &l.reach, error) ||
        !read_number(path, t, label, "stiffness", &l.stiffness, error))
      return false;
    if (const toml::node* side = t.get("side")) {
      const toml::array* a = side->as_array();
      bool good = a != nullptr && a->size() == 3;
      for (size_t i = 0; good && i < 3; ++i) {
        const auto v = a->get(i)->value<double>();
        good = v && std::isfinite(*v);
        if (good) l.side[i] = *v;
      }
      if (!good) return *error = at(path, side, label + " side") + " must be an array of 3 numbers", false;
    }
    o.action_lines.push_back(l);
    return true;
  };
  return each_in(path, e, "jiggle", jiggle, error) && each_in(path, e, "bulge", bulge, error) &&
         each_in(path, e, "action_line", action_line, error);
}

}  // namespace

bool read_toml_layers(const std::string& path, const toml::table& t, layers::LayerSpecs* out, std::string* error) {
  layers::LayerSpecs s;
  if (const toml::table* rig = t["rig"].as_table())
    if (!read_int(path, *rig, "[rig]", "rate_hz", 13, 100000, &s.rate_hz, error)) return false;
  auto each = [&](const char* name, auto&& read) -> bool {
    const toml::node* n = t.get(name);
    if (n == nullptr) return true;
    const toml::array* a = n->as_array();
    if (a == nullptr)
      return *error = at(path, n, std::string("[[") + name + "]]") + " must be an array of tables", false;
    for (const toml::node& e : *a) {
      const toml::table* tt = table_of(e);
      if (tt == nullptr) return *error = at(path, &e, std::string("[[") + name + "]]") + " must be a table", false;
      if (!read(*tt)) return false;
    }
    return true;
  };
  auto single = [&](const char* name, bool* on, std::string* where, auto&& read) -> bool {
    const toml::node* n = t.get(name);
    if (n == nullptr) return true;
    const toml::table* tt = n->as_table();
    if (tt == nullptr) return *error = at(path, n, std::string("[") + name + "]") + " must be a table", false;
    *on = true;
    *where = at(path, n, std::string("[") + name + "]");
    return read(*tt);
  };
  const bool ok =
      each("sph",
           [&](const toml::table& e) {
             layers::SphTable x;
             const std::string n = "[[sph]]";
             if (!known_keys(path, e, n,
                             {"joint", "particles", "radius", "half_length", "tissue_mass", "yield_angle",
                              "force_input", "surface_tension"},
                             error) ||
                 !read_joint(path, e, n, "joint", &x.joint, error) ||
                 !read_int(path, e, n, "particles", 8, 8192, &x.particles, error) ||
                 !read_number(path, e, n, "radius", &x.radius, error) ||
                 !read_number(path, e, n, "half_length", &x.half_length, error) ||
                 !read_number(path, e, n, "tissue_mass", &x.tissue_mass, error) ||
                 !read_number(path, e, n, "yield_angle", &x.yield_angle_deg, error) ||
                 !read_string(path, e, n, "force_input", &x.force_input, error) ||
                 !read_number(path, e, n, "surface_tension", &x.surface_tension, error))
               return false;
             if (x.radius < 0 || x.half_length < 0 || x.tissue_mass < 0 || x.surface_tension < 0 ||
                 !(x.yield_angle_deg > 0 && x.yield_angle_deg < 180))
               return *error = x.joint.where +
                               ": radius, half_length, tissue_mass, surface_tension must be >= 0 and yield_angle in "
                               "(0, 180)",
                      false;
             s.sph.push_back(x);
             return true;
           }) &&
      single("metaballs", &s.metaballs.on, &s.metaballs.where,
             [&](const toml::table& e) { return read_metaballs(path, e, &s.metaballs, error); }) &&
      each("muscle",
           [&](const toml::table& e) {
             layers::MuscleTable x;
             const std::string n = "[[muscle]]";
             x.where = at(path, &e, n);
             const toml::node* side = e.get("side");
             if (!known_keys(path, e, n,
                             {"name", "origin", "insertion", "side", "thickness", "end_axes", "pivot", "slice",
                              "belly_taper", "belly_twist", "belly_bend", "belly_exponent", "belly_exponent_z", "band"},
                             error) ||
                 !read_muscle_shape(path, e, n, &x, error) || !read_string(path, e, n, "name", &x.name, error) ||
                 !read_bool(path, e, n, "band", &x.band, error) ||
                 !read_joint(path, e, n, "origin", &x.origin, error) ||
                 !read_joint(path, e, n, "insertion", &x.insertion, error) ||
                 !read_number(path, e, n, "thickness", &x.thickness, error))
               return false;
             if (side != nullptr) {
               const toml::array* a = side->as_array();
               bool good = a != nullptr && a->size() == 3;
               for (size_t i = 0; good && i < 3; ++i) {
                 const auto v = a->get(i)->value<double>();
                 good = v && std::isfinite(*v);
                 if (good) x.side[i] = *v;
               }
               if (!good) return *error = at(path, side, n + " side") + " must be an array of 3 numbers", false;
             }
             if (!(x.thickness > 0)) return *error = x.where + " thickness must be > 0", false;
             if (x.name.empty()) x.name = "muscle" + std::to_string(s.muscles.size());
             s.muscles.push_back(x);
             return true;
           }) &&
      each("rubber_band",
           [&](const toml::table& e) {
             // LEMAN §5.5; the muscle's name and the skin vertex are resolved
             // by compile_layers, which knows the muscles and the mesh.
             layers::RubberBandTable x;
             const std::string n = "[[rubber_band]]";
             x.where = at(path, &e, n);
             if (!known_keys(path, e, n, {"muscle", "slice", "ring_vertex", "vertex", "stiffness"}, error) ||
                 !read_string(path, e, n, "muscle", &x.muscle, error) ||
                 !read_int(path, e, n, "slice", 0, 7, &x.slice, error) ||
                 !read_int(path, e, n, "ring_vertex", 0, 1023, &x.ring_vertex, error) ||
                 !read_int(path, e, n, "vertex", 0, INT32_MAX, &x.vertex, error) ||
                 !read_number(path, e, n, "stiffness", &x.stiffness, error))
               return false;
             if (x.muscle.empty()) return *error = x.where + " muscle must name a [[muscle]]", false;
             if (!(x.stiffness > 0 && x.stiffness <= 256))
               return *error = x.where + " stiffness must be in (0, 256] (the skin springs' units)", false;
             s.rubber_bands.push_back(x);
             return true;
           }) &&
      single("skin", &s.skin.on, &s.skin.where,
             [&](const toml::table& e) {
               const std::string n = "[skin]";
               anatomy_build::SkinSolverSpec& d = s.skin.solver;
               if (!known_keys(path, e, n,
                               {"iterations",
                                "warm_start",
                                "mode",
                                "tolerance",
                                "fat",
                                "substep_hz",
                                "max_substeps",
                                "constraint_passes",
                                "vertex_mass",
                                "stiffness_scale",
                                "anchor_damping",
                                "band_damping",
                                "edge_damping",
                                "gravity",
                                "fat_normal",
                                "base_acceleration",
                                "surface_density",
                                "frequency",
                                "damping_ratio",
                                "fat_vertices"},
                               error) ||
                   !read_int(path, e, n, "iterations", 1, 256, &s.skin.iterations, error) ||
                   !read_bool(path, e, n, "warm_start", &s.skin.warm_start, error) ||
                   !read_string(path, e, n, "mode", &s.skin.mode, error) ||
                   !read_number(path, e, n, "tolerance", &d.tolerance, error) ||
                   !read_number(path, e, n, "fat", &d.fat_global, error) ||
                   !read_int(path, e, n, "substep_hz", 1, 1 << 20, &d.substep_hz, error) ||
                   !read_int(path, e, n, "max_substeps", 1, 64, &d.max_substeps, error) ||
                   !read_int(path, e, n, "constraint_passes", 1, 4, &d.constraint_passes, error) ||
                   !read_number(path, e, n, "vertex_mass", &d.vertex_mass, error) ||
                   !read_number(path, e, n, "stiffness_scale", &d.stiffness_scale, error) ||
                   !read_number(path, e, n, "anchor_damping", &d.anchor_damping, error) ||
                   !read_number(path, e, n, "band_damping", &d.band_damping, error) ||
                   !read_number(path, e, n, "surface_density", &d.surface_density, error) ||
                   !read_number(path, e, n, "frequency", &d.frequency, error) ||
                   !read_number(path, e, n, "damping_ratio", &d.damping_ratio, error) ||
                   !read_number(path, e, n, "edge_damping", &d.edge_damping, error) ||
                   !in_range(path, e, n, "edge_damping", d.edge_damping >= 0, ">= 0 (N s per model unit)", error))
                 return false;
               if (const toml::node* g = e.get("gravity")) {
                 const toml::array* a = g->as_array();
                 bool good = a != nullptr && a->size() == 3;
                 for (size_t i = 0; good && i < 3; ++i) {
                   const auto v = a->get(i)->value<double>();
                   good = v && std::isfinite(*v);
                   if (good) d.gravity[i] = *v;
                 }
                 if (!good) return *error = at(path, g, n + " gravity") + " must be an array of 3 numbers", false;
               }
               if (const toml::node* b = e.get("base_acceleration")) {
                 const toml::array* a = b->as_array();
                 bool good = a != nullptr && a->size() == 3;
                 for (size_t i = 0; good && i < 3; ++i) {
                   const auto v = a->get(i)->value<std::string>();
                   good = v && !v->empty();
                   if (good) s.skin.base_acceleration.push_back(*v);
                 }
                 if (!good)
                   return *error =
                              at(path, b, n + " base_acceleration") +
                              " must name 3 external inputs (x, y, z), e.g. [\"base.ax\", \"base.ay\", \"base.az\"]",
                          false;
               }
               if (const toml::node* f = e.get("fat_vertices")) {
                 // LEMAN §5.6's per-point thickness: [[vertex, thickness], ...].
                 const toml::array* a = f->as_array();
                 bool good = a != nullptr;
                 for (size_t i = 0; good && i < a->size(); ++i) {
                   const toml::array* pair = a->get(i)->as_array();
                   good = pair != nullptr && pair->size() == 2;
                   const auto v = good ? pair->get(0)->value_exact<int64_t>() : std::nullopt;
                   const auto t = good ? pair->get(1)->value<double>() : std::nullopt;
                   good = v && t && *v >= 0 && *v <= INT32_MAX && std::isfinite(*t) && *t >= 0;
                   if (good) s.skin.fat_vertices.emplace_back(static_cast<int>(*v), *t);
                 }
                 if (!good)
                   return *error = at(path, f, n + " fat_vertices") +
                                   " must be an array of [vertex, thickness] pairs (vertex an index >= 0, thickness "
                                   ">= 0 in model units)",
                          false;
               }
               std::string fat_normal = "anchor";
               if (!read_string(path, e, n, "fat_normal", &fat_normal, error)) return false;
               if (fat_normal != "anchor" && fat_normal != "surface")
                 return *error = at(path, &e, n) + " fat_normal must be \"anchor\" or \"surface\"", false;
               d.fat_surface_normal = fat_normal == "surface";
               if (s.skin.mode != "static" && s.skin.mode != "dynamic")
                 return *error = at(path, &e, n) + " mode must be \"static\" or \"dynamic\"", false;
               d.dynamic = s.skin.mode == "dynamic";
               // Absent tissue values are derived by the builder (docs/anatomy.md,
               // "Physical defaults"); given ones must be physical.
               if (d.tolerance < 0 || d.fat_global < 0 || d.stiffness_scale < 0 ||
                   (e.contains("anchor_damping") && d.anchor_damping < 0) ||
                   (e.contains("band_damping") && d.band_damping < 0))
                 return *error = at(path, &e, n) +
                                 " tolerance, fat, stiffness_scale, anchor_damping and band_damping must be >= 0",
                        false;
               if (e.contains("vertex_mass") && !(d.vertex_mass > 0 && d.vertex_mass < 128))
                 return *error = at(path, &e, n) + " vertex_mass must be in (0, 128) kg", false;
               if (!(d.surface_density > 0 && d.surface_density < 1000))
                 return *error = at(path, &e, n) + " surface_density must be in (0, 1000) kg/m^2", false;
               if (!(d.frequency > 0 && d.frequency <= 1000))
                 return *error = at(path, &e, n) + " frequency must be in (0, 1000] Hz", false;
               if (!(d.damping_ratio >= 0 && d.damping_ratio <= 10))
                 return *error = at(path, &e, n) + " damping_ratio must be in [0, 10]", false;
               return true;
             }) &&
      each("barnet",
           [&](const toml::table& e) {
             layers::BarnetTable x;
             const std::string n = "[[barnet]]";
             if (!known_keys(path, e, n,
                             {"joint", "net", "segments", "rings", "ring_step", "force", "force_input",
                              "force_input_full", "q_input"},
                             error) ||
                 !read_joint(path, e, n, "joint", &x.joint, error) ||
                 !read_int(path, e, n, "segments", 3, 32, &x.segments, error) ||
                 !read_int(path, e, n, "rings", 5, 15, &x.rings, error) ||
                 !read_number(path, e, n, "ring_step", &x.ring_step, error) ||
                 !read_number(path, e, n, "force", &x.force, error) ||
                 !read_string(path, e, n, "force_input", &x.force_input, error) ||
                 !read_number(path, e, n, "force_input_full", &x.force_input_full, error) ||
                 !read_string(path, e, n, "q_input", &x.q_input, error) ||
                 !read_string(path, e, n, "net", &x.net, error))
               return false;
             if (x.net != "joint" && x.net != "muscles" && x.net != "wrinkles" && x.net != "arm-muscles" &&
                 x.net != "arm-wrinkles")
               return *error = x.joint.where +
                               ": net must be \"joint\", \"muscles\", \"wrinkles\", \"arm-muscles\" or "
                               "\"arm-wrinkles\"",
                      false;
             if (x.net == "muscles" && x.segments % 2 != 0)
               return *error = x.joint.where + ": segments must be even for net = \"muscles\"", false;
             if (x.ring_step < 0 || x.force < 0)
               return *error = x.joint.where + ": ring_step and force must be >= 0", false;
             if (!(x.force_input_full != 0 && std::fabs(x.force_input_full) <= 32767))
               return *error = x.joint.where + ": force_input_full must be non-zero, within +-32767", false;
             s.barnets.push_back(x);
             return true;
           }) &&
      each("external_input", [&](const toml::table& e) {
        layers::ExternalInputTable x;
        const std::string n = "[[external_input]]";
        x.where = at(path, &e, n);
        if (!known_keys(path, e, n, {"name", "unit", "quantity", "min", "max"}, error) ||
            !read_string(path, e, n, "name", &x.name, error) || !read_string(path, e, n, "unit", &x.unit, error) ||
            !read_string(path, e, n, "quantity", &x.quantity, error) ||
            !read_number(path, e, n, "min", &x.min, error) || !read_number(path, e, n, "max", &x.max, error))
          return false;
        if (x.name.empty() || !e.contains("min") || !e.contains("max"))
          return *error = x.where + ": name, unit, min and max are required", false;
        s.external.push_back(x);
        return true;
      });
  if (!ok) return false;
  *out = std::move(s);
  return true;
}

}  // namespace sinew::rigc
