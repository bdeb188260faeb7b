#include "sph_compile.hpp"

#include <algorithm>

#include "host_tools/layers/sph/sph_builder.hpp"
#include "host_tools/layers/sph/sph_section_writer.hpp"
#include "sim_core/sph/sph_model.hpp"

namespace sinew::layers {
namespace {

// "<joint>.force", or "sph<i>.force" where the joint's name is too long for
// an input name; the table's force_input if it names one.
bool force_input_name(const rigc::RigSpec& spec, const SphTable& t, size_t i, std::string* name, std::string* error) {
  const int j = resolve_joint(spec, t.joint, error);
  if (j < 0) return false;
  const std::string automatic = spec.joints[static_cast<size_t>(j)].name + ".force";
  *name = !t.force_input.empty()               ? t.force_input
          : automatic.size() < rig::kNameBytes ? automatic
                                               : "sph" + std::to_string(i) + ".force";
  return true;
}

}  // namespace

void HostLayer<pipeline::Stage::kSph>::bent_joints(const Tables& tables, std::vector<const JointRef*>* joints) {
  for (const SphTable& t : tables) joints->push_back(&t.joint);
}

bool HostLayer<pipeline::Stage::kSph>::declare_inputs(const rigc::RigSpec& spec, const Tables& tables,
                                                      std::vector<ExternalInputTable>* external, std::string* error) {
  for (size_t i = 0; i < tables.size(); ++i) {
    std::string name;
    if (!force_input_name(spec, tables[i], i, &name, error)) return false;
    declare_input(external, {name, "N", "force", -40, 40, tables[i].joint.where});
  }
  return true;
}

bool HostLayer<pipeline::Stage::kSph>::compile(const LayerCompile& c, const Tables& tables, std::string* error) {
  const rigc::RigSpec& spec = c.spec;
  const RigGeometry& g = c.geometry;
  if (tables.size() > sinew::sph::kMaxSphJoints) return layer_fail("[[sph]]", "at most 8 SPH joints", error);
  for (size_t i = 0; i < tables.size(); ++i) {
    const SphTable& t = tables[i];
    const int j = resolve_joint(spec, t.joint, error);
    if (j < 0) return false;
    const int parent = anatomical_parent(spec, g, j);
    if (parent < 0)
      return layer_fail(t.joint.where,
                        "joint '" + spec.joints[static_cast<size_t>(j)].name +
                            "' is a root: the SPH tissue spans the bend between its parent's bone and its own",
                        error);
    double skin = 0;
    int radii = 0;
    for (int k : {parent, j})
      if (g.skin_radius[static_cast<size_t>(k)] > 0) skin += g.skin_radius[static_cast<size_t>(k)], ++radii;
    if (radii == 0) return layer_fail(t.joint.where, "no skin vertex is weighted to the joint or its parent", error);
    skin /= radii;
    SphBuildOptions o;
    o.proximal_index = parent;
    o.distal_index = j;
    o.particle_count = t.particles;
    o.capsule_radius = t.radius > 0 ? t.radius : 0.8 * skin;
    const double shorter = std::min(g.bone_length[static_cast<size_t>(parent)], g.bone_length[static_cast<size_t>(j)]);
    o.capsule_half_length = t.half_length > 0 ? t.half_length : std::min(2.2 * o.capsule_radius, 0.4 * shorter);
    const double r = o.capsule_radius, h = o.capsule_half_length;
    o.tissue_mass = t.tissue_mass > 0 ? t.tissue_mass : 1000 * 3.14159265358979323846 * r * r * (2 * h + 4.0 / 3.0 * r);
    o.load_distance = g.bone_length[static_cast<size_t>(j)] > 0 ? g.bone_length[static_cast<size_t>(j)] : 2 * h;
    o.yield_angle_deg = t.yield_angle_deg;
    o.surface_tension = t.surface_tension;
    o.tick_hz = c.rate_hz;
    o.substeps = sph::substeps_for_rate(c.rate_hz);
    SphBuilt built;
    if (!build_sph(spec, o, &built, error)) return layer_fail(t.joint.where, *error, error);
    std::string force_name;
    if (!force_input_name(spec, t, i, &force_name, error)) return false;
    c.sections->push_back(sph_section(built.model(), c.rate_hz, c.input_index(force_name)));
    c.report->push_back("sph[" + std::to_string(i) + "] " + spec.joints[static_cast<size_t>(j)].name + ": " +
                        std::to_string(t.particles) + " particles in a capsule r " + report_number(r) + " x 2 x " +
                        report_number(h) + ", h " + report_number(built.h_metres) + ", " +
                        std::to_string(built.skin_vertex.size()) + " skin vertices, " + report_number(o.tissue_mass) +
                        " kg, built for " + std::to_string(c.rate_hz) + " Hz (" + std::to_string(o.substeps) +
                        " substeps), force input " + force_name);
  }
  return true;
}

}  // namespace sinew::layers
