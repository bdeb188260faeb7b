#include "anatomy_compile.hpp"

#include <algorithm>
#include <cmath>

#include "host_tools/layers/anatomy/anatomy_build.hpp"
#include "host_tools/layers/anatomy/anatomy_section_writer.hpp"
#include "host_tools/layers/anatomy/joint_anatomy.hpp"

namespace sinew::layers {

bool HostLayer<pipeline::Stage::kAnatomy>::declare_inputs(const rigc::RigSpec&, const Tables& tables,
                                                          std::vector<ExternalInputTable>* external, std::string*) {
  for (const std::string& name : tables.skin.base_acceleration)
    declare_input(external, {name, "m/s^2", "acceleration", -200, 200, tables.skin.where});
  return true;
}

bool HostLayer<pipeline::Stage::kAnatomy>::compile(const LayerCompile& c, const Tables& tables, std::string* error) {
  if (tables.muscles.empty() && !tables.skin.on) return true;
  const rigc::RigSpec& spec = c.spec;
  const RigGeometry& g = c.geometry;
  if (tables.muscles.empty())
    return layer_fail(tables.skin.where, "the elastic skin needs at least one [[muscle]]", error);
  std::vector<anatomy_build::MuscleRequest> requests;
  for (const MuscleTable& m : tables.muscles) {
    anatomy_build::MuscleRequest r;
    r.name = m.name;
    if ((r.origin = resolve_joint(spec, m.origin, error)) < 0) return false;
    if ((r.insertion = resolve_joint(spec, m.insertion, error)) < 0) return false;
    r.side = m.side;
    r.thickness = m.thickness;
    r.end_axes_from_bones = m.end_axes_from_bones;
    r.pivot = m.pivot;
    r.slice_edit = m.slice_edit;
    r.belly_taper = m.belly_taper;
    r.belly_twist = m.belly_twist;
    r.belly_bend = m.belly_bend;
    r.belly_exponent = m.belly_exponent;
    r.belly_exponent_z = m.belly_exponent_z;
    r.band = m.band;
    requests.push_back(r);
  }
  anatomy_build::SkinRequest skin;
  skin.iterations = tables.skin.iterations;
  skin.warm_start = tables.skin.warm_start;
  skin.solver = tables.skin.solver;
  if (!tables.rubber_bands.empty() && !tables.skin.on)
    return layer_fail(tables.rubber_bands.front().where, "rubber bands bind the skin: they need a [skin] table", error);
  for (const RubberBandTable& b : tables.rubber_bands) {
    int muscle = -1;
    for (size_t i = 0; i < tables.muscles.size(); ++i)
      if (tables.muscles[i].name == b.muscle) muscle = static_cast<int>(i);
    if (muscle < 0) return layer_fail(b.where, "muscle \"" + b.muscle + "\" is not a [[muscle]] name", error);
    if (b.vertex >= 0 && static_cast<size_t>(b.vertex) >= spec.vertices.size())
      return layer_fail(b.where,
                        "vertex " + std::to_string(b.vertex) + " is beyond the mesh's " +
                            std::to_string(spec.vertices.size()) + " vertices",
                        error);
    skin.bands.push_back({b.vertex, muscle, b.slice, b.ring_vertex, b.stiffness, b.where});
  }
  for (const auto& [v, t] : tables.skin.fat_vertices)
    if (static_cast<size_t>(v) >= spec.vertices.size())
      return layer_fail(tables.skin.where,
                        "fat_vertices: vertex " + std::to_string(v) + " is beyond the mesh's " +
                            std::to_string(spec.vertices.size()) + " vertices",
                        error);
  skin.fat_overrides = tables.skin.fat_vertices;
  anatomy_build::AnatomySpec anatomy;
  std::vector<anatomy_build::MusclePath> paths;
  const std::string& where = tables.muscles.front().where;
  if (!anatomy_build::joint_anatomy(spec, g, requests, skin, &anatomy, &paths, error))
    return layer_fail(where, *error, error);
  for (const RubberBandTable& b : tables.rubber_bands)
    if (b.ring_vertex >= anatomy.ring_vertices)
      return layer_fail(b.where,
                        "ring_vertex " + std::to_string(b.ring_vertex) + " is beyond the muscles' " +
                            std::to_string(anatomy.ring_vertices) + " ring vertices",
                        error);
  anatomy_build::AnatomyModel model;
  if (!anatomy_build::build_anatomy(c.rig, anatomy, &model, error)) {
    for (const RubberBandTable& b : tables.rubber_bands)
      if (error->rfind(b.where, 0) == 0) return false;  // the band's own table is named already
    return layer_fail(where, *error, error);
  }
  c.sections->push_back(muscles_section(model.muscle_model()));
  c.report->push_back("muscles: " + std::to_string(model.muscles.size()) + " with " +
                      std::to_string(model.primitives.size()) + " primitives");
  if (tables.skin.on) {
    // The skin's support region: full weight within one skin radius of a
    // muscle's surface, none beyond 2.5 (a smoothstep between), so the
    // skin far from every muscle keeps the skinned pose bit for bit.
    std::vector<uint32_t> region;
    std::vector<fx::Unit> weight;
    double mean_radius = 0;
    int radii = 0;
    for (double r : g.skin_radius)
      if (r > 0) mean_radius += r, ++radii;
    mean_radius /= std::max(radii, 1);
    for (size_t v = 0; v < spec.vertices.size(); ++v) {
      double w = 0;
      for (const anatomy_build::MusclePath& m : paths) {
        const Vec3d axis = sub(m.insertion, m.origin), rel = sub(spec.vertices[v].position, m.origin);
        const double len2 = dot(axis, axis);
        const double t = len2 > 0 ? std::clamp(dot(rel, axis) / len2, 0.0, 1.0) : 0.0;
        const double d = norm(sub(rel, scaled(axis, t))) - m.half_width;
        const double inner = mean_radius, outer = 2.5 * mean_radius;
        const double x = std::clamp((d - inner) / (outer - inner), 0.0, 1.0);
        w = std::max(w, 1 - x * x * (3 - 2 * x));
      }
      const fx::Unit q = static_cast<fx::Unit>(std::floor(w * 1073741824.0 + 0.5));
      if (q > 0) region.push_back(static_cast<uint32_t>(v)), weight.push_back(q);
    }
    uint32_t base[3] = {pipeline::kNoExternalInput, pipeline::kNoExternalInput, pipeline::kNoExternalInput};
    if (!tables.skin.base_acceleration.empty()) {
      if (tables.skin.base_acceleration.size() != 3)
        return layer_fail(tables.skin.where, "base_acceleration must name 3 inputs (x, y, z)", error);
      for (size_t axis = 0; axis < 3; ++axis) {
        const std::string& name = tables.skin.base_acceleration[axis];
        base[axis] = c.input_index(name);  // declared by declare_inputs if the spec does not
        if (base[axis] == pipeline::kNoExternalInput ||
            c.inputs[base[axis]].quantity != static_cast<uint32_t>(pipeline::InputQuantity::kAcceleration))
          return layer_fail(tables.skin.where, "base_acceleration input '" + name + "' is not an acceleration", error);
      }
    }
    c.sections->push_back(skin_section(model.skin_model(), region, weight, base));
    c.report->push_back("elastic skin region: " + std::to_string(region.size()) + " of " +
                        std::to_string(spec.vertices.size()) + " vertices");
    c.report->push_back("elastic skin: " + std::to_string(model.report.muscle_anchors) + " muscle anchors, " +
                        std::to_string(model.report.bone_anchors) + " bone anchors, " +
                        std::to_string(model.report.edges) + " springs, " + std::to_string(model.report.bands) +
                        " rubber bands, " + std::to_string(tables.skin.iterations) + " relaxations per tick");
    if (tables.skin.solver.dynamic)
      c.report->push_back("elastic skin, dynamic: " + report_number(model.report.vertex_mass * 1e3) + " g a vertex, " +
                          report_number(model.report.stiffness_scale) + " N/m and " +
                          report_number(model.report.anchor_damping) + " N s/m per unit stiffness, stiffest mode " +
                          report_number(model.report.omega_max) + " rad/s, " + std::to_string(model.report.substep_hz) +
                          " Hz substeps");
  }
  return true;
}

}  // namespace sinew::layers
