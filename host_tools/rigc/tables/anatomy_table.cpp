#include "anatomy_table.hpp"

#include <cmath>
#include <cstdint>
#include <optional>

#include "host_tools/rigc/toml_reader.hpp"

namespace sinew::rigc {

using namespace spec_read;

namespace {

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

}  // namespace

bool RigcTable<pipeline::Stage::kAnatomy>::read(const std::string& path, const toml::table& root, Tables* out,
                                                std::string* error) {
  return each_table(
             path, root, "muscle",
             [&](const toml::table& e) {
               layers::MuscleTable x;
               const std::string n = "[[muscle]]";
               x.where = at(path, &e, n);
               if (!known_keys(
                       path, e, n,
                       {"name", "origin", "insertion", "side", "thickness", "end_axes", "pivot", "slice", "belly_taper",
                        "belly_twist", "belly_bend", "belly_exponent", "belly_exponent_z", "band"},
                       error) ||
                   !read_muscle_shape(path, e, n, &x, error) || !read_string(path, e, n, "name", &x.name, error) ||
                   !read_bool(path, e, n, "band", &x.band, error) ||
                   !read_joint(path, e, n, "origin", &x.origin, error) ||
                   !read_joint(path, e, n, "insertion", &x.insertion, error) ||
                   !read_number(path, e, n, "thickness", &x.thickness, error))
                 return false;
               if (!read_vec3(path, e, n, "side", x.side.data(), error)) return false;
               if (!(x.thickness > 0)) return *error = x.where + " thickness must be > 0", false;
               if (x.name.empty()) x.name = "muscle" + std::to_string(out->muscles.size());
               out->muscles.push_back(x);
               return true;
             },
             error) &&
         each_table(
             path, root, "rubber_band",
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
               out->rubber_bands.push_back(x);
               return true;
             },
             error) &&
         single_table(
             path, root, "skin", &out->skin.on, &out->skin.where,
             [&](const toml::table& e) {
               const std::string n = "[skin]";
               anatomy_build::SkinSolverSpec& d = out->skin.solver;
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
                                "fat_vertices",
                                "integrator",
                                "relaxation_iterations",
                                "bend",
                                "pressure",
                                "reaction_frequency"},
                               error) ||
                   !read_int(path, e, n, "iterations", 1, 256, &out->skin.iterations, error) ||
                   !read_bool(path, e, n, "warm_start", &out->skin.warm_start, error) ||
                   !read_string(path, e, n, "mode", &out->skin.mode, error) ||
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
                   !in_range(path, e, n, "edge_damping", d.edge_damping >= 0, ">= 0 (N s per model unit)", error) ||
                   !read_int(path, e, n, "relaxation_iterations", 1, 8, &d.relaxation_iterations, error) ||
                   !read_number(path, e, n, "bend", &d.bend, error) ||
                   !in_range(path, e, n, "bend", d.bend >= 0 && d.bend <= 256, "in [0, 256] (model stiffness)",
                             error) ||
                   !read_number(path, e, n, "pressure", &d.pressure, error) ||
                   !in_range(path, e, n, "pressure", d.pressure > -1e6 && d.pressure < 1e6, "within +-1e6 N/m^2",
                             error) ||
                   !read_number(path, e, n, "reaction_frequency", &d.reaction_frequency, error) ||
                   !in_range(path, e, n, "reaction_frequency",
                             d.reaction_frequency >= 0 && d.reaction_frequency <= 10000, "in (0, 10000] Hz", error))
                 return false;
               std::string integrator = "relaxation";
               if (!read_string(path, e, n, "integrator", &integrator, error)) return false;
               if (integrator != "relaxation" && integrator != "explicit")
                 return *error = at(path, &e, n) + " integrator must be \"relaxation\" or \"explicit\"", false;
               d.relaxation = integrator == "relaxation";
               if (!read_vec3(path, e, n, "gravity", d.gravity, error)) return false;
               if (const toml::node* b = e.get("base_acceleration")) {
                 const toml::array* a = b->as_array();
                 bool good = a != nullptr && a->size() == 3;
                 for (size_t i = 0; good && i < 3; ++i) {
                   const auto v = a->get(i)->value<std::string>();
                   good = v && !v->empty();
                   if (good) out->skin.base_acceleration.push_back(*v);
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
                   if (good) out->skin.fat_vertices.emplace_back(static_cast<int>(*v), *t);
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
               if (out->skin.mode != "static" && out->skin.mode != "dynamic")
                 return *error = at(path, &e, n) + " mode must be \"static\" or \"dynamic\"", false;
               d.dynamic = out->skin.mode == "dynamic";
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
             },
             error);
}

}  // namespace sinew::rigc
