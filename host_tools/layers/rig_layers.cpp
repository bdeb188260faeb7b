#include "rig_layers.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <sstream>

#include "host_tools/layers/anatomy/anatomy_build.hpp"
#include "host_tools/layers/anatomy/anatomy_section_writer.hpp"
#include "host_tools/layers/anatomy/joint_anatomy.hpp"
#include "host_tools/layers/barnet/barnet_section_writer.hpp"
#include "host_tools/layers/barnet/joint_net.hpp"
#include "host_tools/layers/barnet/muscle_net.hpp"
#include "host_tools/layers/barnet/wrinkle_net.hpp"
#include "host_tools/layers/common/rig_geometry.hpp"
#include "host_tools/layers/metaballs/builder.hpp"
#include "host_tools/layers/metaballs/metaballs_section_writer.hpp"
#include "host_tools/layers/sections/layer_writer.hpp"
#include "host_tools/layers/sph/sph_builder.hpp"
#include "host_tools/layers/sph/sph_section_writer.hpp"
#include "host_tools/rigc/builtin_rigs.hpp"
#include "sim_core/rig/rig.hpp"
#include "sim_core/sph/sph_model.hpp"

namespace sinew::layers {
namespace {

std::string fmt(double v) {
  std::ostringstream s;
  s.precision(4);
  s << v;
  return s.str();
}

bool fail(const std::string& where, const std::string& problem, std::string* error) {
  *error = where.empty() ? problem : where + ": " + problem;
  return false;
}

bool quantity_of(const std::string& name, pipeline::InputQuantity* out) {
  if (name == "force") return *out = pipeline::InputQuantity::kForce, true;
  if (name == "length") return *out = pipeline::InputQuantity::kLength, true;
  if (name == "angle") return *out = pipeline::InputQuantity::kAngle, true;
  if (name == "scalar") return *out = pipeline::InputQuantity::kScalar, true;
  if (name == "acceleration") return *out = pipeline::InputQuantity::kAcceleration, true;
  return false;
}

int32_t q16(double v) {
  const double s = std::floor(v * 65536.0 + 0.5);
  return static_cast<int32_t>(std::clamp(s, -2147483648.0, 2147483647.0));
}

}  // namespace

int resolve_joint(const rigc::RigSpec& spec, const JointRef& ref, std::string* error) {
  if (ref.node >= 0) {
    for (size_t j = 0; j < spec.source_node.size(); ++j)
      if (spec.source_node[j] == ref.node) return static_cast<int>(j);
    fail(ref.where,
         spec.source_node.empty() ? "joint by node index needs a glTF source"
                                  : "no joint of the rig comes from glTF node " + std::to_string(ref.node),
         error);
    return -1;
  }
  int j = rigc::joint_index(spec, ref.name);
  // A glTF name longer than the rig's 31 name bytes was truncated at import.
  if (j < 0 && ref.name.size() >= rig::kNameBytes) {
    size_t n = rig::kNameBytes - 1;
    while (n > 0 && (static_cast<unsigned char>(ref.name[n]) & 0xC0u) == 0x80u) --n;
    j = rigc::joint_index(spec, ref.name.substr(0, n));
  }
  if (j < 0) fail(ref.where, "no joint named '" + ref.name + "'", error);
  return j;
}

bool add_layer_dofs(rigc::RigSpec* spec, const LayerSpecs& layers, std::vector<std::string>* report,
                    std::string* error) {
  std::vector<const JointRef*> refs;
  for (const SphTable& t : layers.sph) refs.push_back(&t.joint);
  for (const BarnetTable& t : layers.barnets) refs.push_back(&t.joint);
  if (refs.empty()) return true;
  RigGeometry g;
  if (!rig_geometry(*spec, &g, error)) return false;
  for (const JointRef* ref : refs) {
    const int j = resolve_joint(*spec, *ref, error);
    if (j < 0) return false;
    rigc::JointSpec& js = spec->joints[static_cast<size_t>(j)];
    if (!js.dofs.empty()) continue;
    const int parent = anatomical_parent(*spec, g, j);
    if (parent < 0)
      return fail(ref->where, "joint '" + js.name + "' is a root: a layer bends the joint between two bones", error);
    const Vec3d up = g.bone_dir[static_cast<size_t>(parent)], uj = g.bone_dir[static_cast<size_t>(j)];
    Vec3d axis = cross(up, uj);
    if (!(norm(axis) > 0.1)) axis = perpendicular(up);
    const Vec3d local = dir_to_local(g.frame[static_cast<size_t>(j)], normalized(axis));
    js.dof_kind = rigc::DofKind::kRotation;
    js.dofs.push_back({local, -150, 150});
    report->push_back("joint '" + js.name + "' gets one rotational DOF about its bend axis (" + fmt(local[0]) + ", " +
                      fmt(local[1]) + ", " + fmt(local[2]) + ") in its frame, +-150 degrees");
  }
  return true;
}

bool compile_layers(const rigc::RigSpec& spec, const LayerSpecs& layers, std::vector<uint8_t>* blob,
                    std::vector<std::string>* report, std::string* error) {
  if (layers.empty()) return true;
  if (layers.rate_hz < 13 || layers.rate_hz > 100000)
    return fail("[rig] rate_hz", "must be 13..100000 (the SPH substeps cover at most 80 ms)", error);
  RigGeometry g;
  if (!rig_geometry(spec, &g, error)) return false;
  // The compiled core, loaded as the board will: the anatomy builder works
  // from it, and every layer is checked against it.
  std::vector<uint64_t> core(blob->size() / 8 + 1);
  std::memcpy(core.data(), blob->data(), blob->size());
  const auto* core_bytes = reinterpret_cast<const uint8_t*>(core.data());
  size_t arena_bytes = 0;
  rig::LoadStatus st = rig::rig_validate(core_bytes, blob->size(), &arena_bytes);
  std::vector<uint64_t> arena(arena_bytes / 8 + 1);
  rig::Rig rig;
  if (st.ok()) st = rig::rig_init(core_bytes, blob->size(), arena.data(), arena.size() * 8, &rig);
  if (!st.ok()) return fail("", std::string("internal: core blob rejected: ") + st.message, error);

  std::vector<LayerSection> sections;
  // External inputs: the declared ones, then each SPH joint's force if undeclared.
  std::vector<ExternalInputTable> external = layers.external;
  std::vector<std::string> sph_force(layers.sph.size());
  for (size_t i = 0; i < layers.sph.size(); ++i) {
    const int j = resolve_joint(spec, layers.sph[i].joint, error);
    if (j < 0) return false;
    // "<joint>.force", or "sph<i>.force" where the joint's name is too long for an input name.
    const std::string automatic = spec.joints[static_cast<size_t>(j)].name + ".force";
    sph_force[i] = !layers.sph[i].force_input.empty()   ? layers.sph[i].force_input
                   : automatic.size() < rig::kNameBytes ? automatic
                                                        : "sph" + std::to_string(i) + ".force";
    const bool declared = std::any_of(external.begin(), external.end(),
                                      [&](const ExternalInputTable& e) { return e.name == sph_force[i]; });
    if (!declared) external.push_back({sph_force[i], "N", "force", -40, 40, layers.sph[i].joint.where});
  }
  // Each bar-net's force and force-density inputs, if undeclared.
  for (const BarnetTable& t : layers.barnets) {
    auto declare = [&external](const std::string& name, const ExternalInputTable& as) {
      if (name.empty()) return;
      if (std::none_of(external.begin(), external.end(), [&](const ExternalInputTable& e) { return e.name == name; }))
        external.push_back(as);
    };
    declare(t.force_input, {t.force_input, "N", "force", -40, 40, t.joint.where});
    declare(t.q_input, {t.q_input, "", "scalar", 1.0 / 256, 256, t.joint.where});
  }
  // The skin's base-acceleration inputs, if undeclared.
  for (const std::string& name : layers.skin.base_acceleration)
    if (std::none_of(external.begin(), external.end(), [&](const ExternalInputTable& e) { return e.name == name; }))
      external.push_back({name, "m/s^2", "acceleration", -200, 200, layers.skin.where});
  std::vector<pipeline::ExternalInputRecord> records;
  for (const ExternalInputTable& e : external) {
    pipeline::ExternalInputRecord r{};
    if (e.name.empty() || e.name.size() >= sizeof(r.name)) return fail(e.where, "name must be 1..31 characters", error);
    if (e.unit.size() >= sizeof(r.unit)) return fail(e.where, "unit must be at most 15 characters", error);
    pipeline::InputQuantity q;
    if (!quantity_of(e.quantity, &q))
      return fail(e.where, "quantity must be \"force\", \"length\", \"angle\", \"scalar\" or \"acceleration\"", error);
    if (!(e.min < e.max) || std::fabs(e.min) > 32767 || std::fabs(e.max) > 32767)
      return fail(e.where, "min must be below max, both within +-32767", error);
    std::memcpy(r.name, e.name.data(), e.name.size());
    std::memcpy(r.unit, e.unit.data(), e.unit.size());
    r.quantity = static_cast<uint32_t>(q);
    r.min = q16(e.min);
    r.max = q16(e.max);
    records.push_back(r);
  }
  if (records.size() > pipeline::kMaxExternalInputs) return fail("[[external_input]]", "at most 64", error);
  if (!records.empty()) sections.push_back(external_inputs_section(records));

  if (layers.sph.size() > sinew::sph::kMaxSphJoints) return fail("[[sph]]", "at most 8 SPH joints", error);
  for (size_t i = 0; i < layers.sph.size(); ++i) {
    const SphTable& t = layers.sph[i];
    const int j = resolve_joint(spec, t.joint, error);
    if (j < 0) return false;
    const int parent = anatomical_parent(spec, g, j);
    if (parent < 0)
      return fail(t.joint.where,
                  "joint '" + spec.joints[static_cast<size_t>(j)].name +
                      "' is a root: the SPH tissue spans the bend between its parent's bone and its own",
                  error);
    double skin = 0;
    int radii = 0;
    for (int k : {parent, j})
      if (g.skin_radius[static_cast<size_t>(k)] > 0) skin += g.skin_radius[static_cast<size_t>(k)], ++radii;
    if (radii == 0) return fail(t.joint.where, "no skin vertex is weighted to the joint or its parent", error);
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
    o.tick_hz = layers.rate_hz;
    o.substeps = sph::substeps_for_rate(layers.rate_hz);
    SphBuilt built;
    if (!build_sph(spec, o, &built, error)) return fail(t.joint.where, *error, error);
    uint32_t force = pipeline::kNoExternalInput;
    for (size_t k = 0; k < records.size(); ++k)
      if (sph_force[i] == records[k].name) force = static_cast<uint32_t>(k);
    sections.push_back(sph_section(built.model(), layers.rate_hz, force));
    report->push_back("sph[" + std::to_string(i) + "] " + spec.joints[static_cast<size_t>(j)].name + ": " +
                      std::to_string(t.particles) + " particles in a capsule r " + fmt(r) + " x 2 x " + fmt(h) +
                      ", h " + fmt(built.h_metres) + ", " + std::to_string(built.skin_vertex.size()) +
                      " skin vertices, " + fmt(o.tissue_mass) + " kg, built for " + std::to_string(layers.rate_hz) +
                      " Hz (" + std::to_string(o.substeps) + " substeps), force input " + sph_force[i]);
  }

  if (layers.metaballs.on) {
    metaballs_build::Options o = layers.metaballs.options;
    o.rate_hz = layers.rate_hz;  // physical jiggle gains for the rig's tick rate
    double mean = 0, total = 0;
    int radii = 0;
    for (size_t j = 0; j < g.skin_radius.size(); ++j) {
      if (g.skin_radius[j] > 0) mean += g.skin_radius[j], ++radii;
      if (!g.vertices_of[j].empty()) total += g.bone_length[j];
    }
    if (radii == 0) return fail(layers.metaballs.where, "no skin vertex is weighted to any joint", error);
    mean /= radii;
    o.ball_spacing =
        layers.metaballs.ball_spacing > 0 ? layers.metaballs.ball_spacing : std::max(0.22 * mean, total / 3000);
    metaballs_build::Build built;
    if (!metaballs_build::build(spec, o, &built, error)) return fail(layers.metaballs.where, *error, error);
    sections.push_back(metaballs_section(built.model()));
    report->push_back("metaballs: " + std::to_string(built.ball_rest.size()) + " balls " + fmt(o.ball_spacing) +
                      " apart, " + std::to_string(built.joint_balls.size()) + " joint balls, " +
                      std::to_string(built.jv_vertex.size()) + " joint-region vertices");
  }

  if (layers.barnets.size() > sinew::barnet::kMaxBarnets) return fail("[[barnet]]", "at most 8 bar-nets", error);
  for (size_t i = 0; i < layers.barnets.size(); ++i) {
    const BarnetTable& t = layers.barnets[i];
    const int j = resolve_joint(spec, t.joint, error);
    if (j < 0) return false;
    barnet::JointNetOptions o;
    o.segments = t.segments;
    o.rings = t.rings;
    o.ring_step = t.ring_step;
    o.force = t.force;
    o.external_count = static_cast<uint32_t>(records.size());
    for (size_t k = 0; k < records.size(); ++k) {
      if (!t.force_input.empty() && t.force_input == records[k].name) o.force_input = static_cast<int>(k);
      if (!t.q_input.empty() && t.q_input == records[k].name) o.q_input = static_cast<int>(k);
    }
    o.force_input_hi = t.force_input_full;
    barnet::NetSpec net;
    barnet::BarnetBuild built;
    bool built_net = false;
    if (t.net == "joint") {
      built_net = barnet::joint_net(spec, g, j, o, &net, error);
    } else {
      barnet::JointMuscleNetOptions muscles;
      muscles.segments = t.segments;
      muscles.force = t.force;
      barnet::SkinWrinkleOptions wrinkles;
      wrinkles.force = t.force;
      built_net = t.net == "muscles"       ? barnet::joint_muscle_net(spec, g, j, muscles, &net, error)
                  : t.net == "wrinkles"    ? barnet::skin_wrinkle_net(spec, g, j, wrinkles, &net, error)
                  : t.net == "arm-muscles" ? barnet::arm_muscle_net(spec, {}, &net, error)
                                           : barnet::arm_wrinkle_net(spec, {}, &net, error);
      barnet::drive_from_inputs({o.external_count, o.force_input, o.force_input_lo, o.force_input_hi, o.q_input}, &net);
    }
    if (!built_net || !barnet::build_barnet(net, spec, &built, error)) return fail(t.joint.where, *error, error);
    sections.push_back(barnet_section(built.model()));
    report->push_back("barnet[" + std::to_string(i) + "] " + spec.joints[static_cast<size_t>(j)].name + ": " +
                      std::to_string(built.nodes.size()) + " nodes, " + std::to_string(built.bars.size()) + " bars, " +
                      std::to_string(built.loads.size()) + " loads, " + std::to_string(built.wrap.size()) +
                      " wrapped vertices");
  }

  if (!layers.muscles.empty() || layers.skin.on) {
    if (layers.muscles.empty()) return fail(layers.skin.where, "the elastic skin needs at least one [[muscle]]", error);
    std::vector<anatomy_build::MuscleRequest> requests;
    for (const MuscleTable& m : layers.muscles) {
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
    skin.iterations = layers.skin.iterations;
    skin.warm_start = layers.skin.warm_start;
    skin.solver = layers.skin.solver;
    if (!layers.rubber_bands.empty() && !layers.skin.on)
      return fail(layers.rubber_bands.front().where, "rubber bands bind the skin: they need a [skin] table", error);
    for (const RubberBandTable& b : layers.rubber_bands) {
      int muscle = -1;
      for (size_t i = 0; i < layers.muscles.size(); ++i)
        if (layers.muscles[i].name == b.muscle) muscle = static_cast<int>(i);
      if (muscle < 0) return fail(b.where, "muscle \"" + b.muscle + "\" is not a [[muscle]] name", error);
      if (b.vertex >= 0 && static_cast<size_t>(b.vertex) >= spec.vertices.size())
        return fail(b.where,
                    "vertex " + std::to_string(b.vertex) + " is beyond the mesh's " +
                        std::to_string(spec.vertices.size()) + " vertices",
                    error);
      skin.bands.push_back({b.vertex, muscle, b.slice, b.ring_vertex, b.stiffness, b.where});
    }
    for (const auto& [v, t] : layers.skin.fat_vertices)
      if (static_cast<size_t>(v) >= spec.vertices.size())
        return fail(layers.skin.where,
                    "fat_vertices: vertex " + std::to_string(v) + " is beyond the mesh's " +
                        std::to_string(spec.vertices.size()) + " vertices",
                    error);
    skin.fat_overrides = layers.skin.fat_vertices;
    anatomy_build::AnatomySpec anatomy;
    std::vector<anatomy_build::MusclePath> paths;
    const std::string& where = layers.muscles.front().where;
    if (!anatomy_build::joint_anatomy(spec, g, requests, skin, &anatomy, &paths, error))
      return fail(where, *error, error);
    for (const RubberBandTable& b : layers.rubber_bands)
      if (b.ring_vertex >= anatomy.ring_vertices)
        return fail(b.where,
                    "ring_vertex " + std::to_string(b.ring_vertex) + " is beyond the muscles' " +
                        std::to_string(anatomy.ring_vertices) + " ring vertices",
                    error);
    anatomy_build::AnatomyModel model;
    if (!anatomy_build::build_anatomy(rig, anatomy, &model, error)) {
      for (const RubberBandTable& b : layers.rubber_bands)
        if (error->rfind(b.where, 0) == 0) return false;  // the band's own table is named already
      return fail(where, *error, error);
    }
    sections.push_back(muscles_section(model.muscle_model()));
    report->push_back("muscles: " + std::to_string(model.muscles.size()) + " with " +
                      std::to_string(model.primitives.size()) + " primitives");
    if (layers.skin.on) {
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
      if (!layers.skin.base_acceleration.empty()) {
        if (layers.skin.base_acceleration.size() != 3)
          return fail(layers.skin.where, "base_acceleration must name 3 inputs (x, y, z)", error);
        for (size_t c = 0; c < 3; ++c) {
          for (size_t k = 0; k < records.size(); ++k)
            if (layers.skin.base_acceleration[c] == records[k].name) base[c] = static_cast<uint32_t>(k);
          if (records[base[c]].quantity != static_cast<uint32_t>(pipeline::InputQuantity::kAcceleration))
            return fail(layers.skin.where,
                        "base_acceleration input '" + layers.skin.base_acceleration[c] + "' is not an acceleration",
                        error);
        }
      }
      sections.push_back(skin_section(model.skin_model(), region, weight, base));
      report->push_back("elastic skin region: " + std::to_string(region.size()) + " of " +
                        std::to_string(spec.vertices.size()) + " vertices");
      report->push_back("elastic skin: " + std::to_string(model.report.muscle_anchors) + " muscle anchors, " +
                        std::to_string(model.report.bone_anchors) + " bone anchors, " +
                        std::to_string(model.report.edges) + " springs, " + std::to_string(model.report.bands) +
                        " rubber bands, " + std::to_string(layers.skin.iterations) + " relaxations per tick");
      if (layers.skin.solver.dynamic)
        report->push_back("elastic skin, dynamic: " + fmt(model.report.vertex_mass * 1e3) + " g a vertex, " +
                          fmt(model.report.stiffness_scale) + " N/m and " + fmt(model.report.anchor_damping) +
                          " N s/m per unit stiffness, stiffest mode " + fmt(model.report.omega_max) + " rad/s, " +
                          std::to_string(model.report.substep_hz) + " Hz substeps");
    }
  }
  return append_layer_sections(blob, sections, error);
}

}  // namespace sinew::layers
