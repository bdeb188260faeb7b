#include "skin_validate.hpp"

namespace sinew::elastic_skin {
namespace {

LayerStatus bad(const char* what, int64_t index, const char* field, const char* problem, int64_t value = 0,
                bool show = false) {
  return muscle::layer_fail(LayerError::kBadValue, what, index, field, problem, value, show);
}

LayerStatus check_anchor(const Anchor& a, uint32_t v, const muscle::MuscleModel& muscles, uint32_t joints) {
  if (a.kind == static_cast<uint8_t>(AnchorKind::kBone)) {
    if (a.component >= joints || a.bone_b >= joints)
      return bad("skin anchor", v, "component", "bone is not a joint of the rig (anchor outside every component)",
                 a.component, true);
    if (a.weight_b < 0 || a.weight_b > fx::kUnitOne)
      return bad("skin anchor", v, "weight_b", "outside [0, 1]", a.weight_b, true);
    return {};
  }
  if (a.kind != static_cast<uint8_t>(AnchorKind::kMuscle))
    return bad("skin anchor", v, "kind", "unknown", a.kind, true);
  if (a.component >= muscles.muscles.size())
    return bad("skin anchor", v, "component", "no such muscle (anchor outside every component)", a.component, true);
  if (a.segment + 1 >= muscle::kSlices) return bad("skin anchor", v, "segment", "must be 0..6", a.segment, true);
  for (int c = 0; c < 2; ++c)
    if (a.param[c] > kMaxAnchorST || a.param[c] < -kMaxAnchorST)
      return bad("skin anchor", v, "param", "(s, t) beyond +-16: anchor outside every component", a.param[c], true);
  if (a.param[2] < kMinAnchorU || a.param[2] > kMaxAnchorU)
    return bad("skin anchor", v, "param.u", "outside [-1, 2]: anchor outside every component", a.param[2], true);
  return {};
}

LayerStatus check_params(const SkinParams& p) {
  if (p.iterations < 1 || p.iterations > kMaxIterations)
    return bad("skin params", -1, "iterations", "must be 1..256", p.iterations, true);
  if (p.push_back < 0 || p.push_back > fx::kUnitOne)
    return bad("skin params", -1, "push_back", "outside [0, 1]", p.push_back, true);
  if (p.compression_band <= 0 || p.compression_band > fx::kUnitOne)
    return bad("skin params", -1, "compression_band", "outside (0, 1]", p.compression_band, true);
  if (p.reaction_gain <= 0 || p.reaction_gain > fx::kUnitOne)
    return bad("skin params", -1, "reaction_gain", "outside (0, 1]", p.reaction_gain, true);
  if (p.newton_steps < 1 || p.newton_steps > kMaxNewtonSteps)
    return bad("skin params", -1, "newton_steps", "must be 1..8", p.newton_steps, true);
  if (p.collision_radius < 0) return bad("skin params", -1, "collision_radius", "negative", p.collision_radius, true);
  return {};
}

LayerStatus check_solver(const SkinSolverParams& p) {
  if (p.mode > static_cast<uint8_t>(SkinMode::kDynamic)) return bad("skin solver", -1, "mode", "unknown", p.mode, true);
  if (p.tolerance < 0) return bad("skin solver", -1, "tolerance", "negative", p.tolerance, true);
  if (p.fat_thickness < 0) return bad("skin solver", -1, "fat_thickness", "negative", p.fat_thickness, true);
  if (p.fat_normal > static_cast<uint8_t>(FatNormal::kSurface))
    return bad("skin solver", -1, "fat_normal", "unknown", p.fat_normal, true);
  if (p.mode != static_cast<uint8_t>(SkinMode::kDynamic)) return {};
  if (p.substep_hz < 1 || p.substep_hz > kMaxSubstepHz)
    return bad("skin solver", -1, "substep_hz", "must be 1..2^20", p.substep_hz, true);
  if (p.max_substeps < 1 || p.max_substeps > kMaxSubsteps)
    return bad("skin solver", -1, "max_substeps", "must be 1..64", p.max_substeps, true);
  if (p.constraint_passes < 1 || p.constraint_passes > kMaxConstraintPasses)
    return bad("skin solver", -1, "constraint_passes", "must be 1..4", p.constraint_passes, true);
  if (p.vertex_mass <= 0) return bad("skin solver", -1, "vertex_mass", "must be > 0", p.vertex_mass, true);
  if (p.stiffness_scale < 0 || p.anchor_damping < 0 || p.band_damping < 0 || p.edge_damping < 0)
    return bad("skin solver", -1, "stiffness_scale/anchor_damping/band_damping/edge_damping", "negative");
  return {};
}

LayerStatus check_surface(const SkinSurfaceParams& p, bool dynamic) {
  if (!dynamic) return {};
  if (p.integrator > static_cast<uint8_t>(SkinIntegrator::kRelaxation))
    return bad("skin surface", -1, "integrator", "unknown", p.integrator, true);
  if (p.integrator != static_cast<uint8_t>(SkinIntegrator::kRelaxation)) return {};
  if (p.relaxation_iterations < 1 || p.relaxation_iterations > kMaxRelaxationIterations)
    return bad("skin surface", -1, "relaxation_iterations", "must be 1..8", p.relaxation_iterations, true);
  if (p.bend > kMaxStiffness) return bad("skin surface", -1, "bend", "above 256", p.bend, true);
  if (p.reaction_frequency <= 0 || p.reaction_frequency > kMaxReactionFrequency)
    return bad("skin surface", -1, "reaction_frequency", "outside (0, 10000] Hz", p.reaction_frequency, true);
  return {};
}

}  // namespace

LayerStatus skin_check_indices(const SkinModel& model, const muscle::MuscleModel& muscles, uint32_t joints) {
  const uint32_t n = model.vertex_count;
  if (n > kMaxVertices) return bad("skin model", -1, "vertex_count", "above 2^20", n, true);
  if (model.anchors.size() != n || model.anchor_stiffness.size() != n || model.fat.size() != n)
    return bad("skin model", -1, "anchors/anchor_stiffness/fat", "sizes differ from vertex_count", n, true);
  for (uint32_t v = 0; v < n; ++v) {
    const LayerStatus s = check_anchor(model.anchors[v], v, muscles, joints);
    if (!s.ok()) return s;
  }
  for (uint32_t e = 0; e < model.edges.size(); ++e) {
    const Edge& ed = model.edges[e];
    if (ed.a >= n || ed.b >= n || ed.a == ed.b)
      return bad("skin edge", e, "a/b", "endpoint out of range or repeated", ed.a, true);
  }
  const uint32_t ring = muscles.ring_vertices;
  const bool dynamic = model.solver.mode == static_cast<uint8_t>(SkinMode::kDynamic);
  const bool pressure = dynamic && model.surface.integrator == static_cast<uint8_t>(SkinIntegrator::kRelaxation) &&
                        model.surface.pressure != 0;
  if (pressure && model.triangles.empty())
    return bad("skin surface", -1, "pressure", "needs the skin's triangles (none given)", model.surface.pressure, true);
  if (model.solver.fat_normal == static_cast<uint8_t>(FatNormal::kSurface) || pressure) {
    if (model.triangles.size() % 3 != 0)
      return bad("skin model", -1, "triangles", "not 3 indices per face", static_cast<int64_t>(model.triangles.size()),
                 true);
    for (size_t i = 0; i < model.triangles.size(); ++i)
      if (model.triangles[i] >= n)
        return bad("skin triangle", static_cast<int64_t>(i / 3), "vertex", "out of range", model.triangles[i], true);
  }
  for (uint32_t i = 0; i < model.bands.size(); ++i) {
    const RubberBand& b = model.bands[i];
    if (b.vertex >= n || b.muscle >= muscles.muscles.size() || b.slice >= muscle::kSlices || b.ring_vertex >= ring)
      return bad("rubber band", i, "vertex/muscle/slice/ring_vertex", "out of range");
    if (b.k > kMaxStiffness) return bad("rubber band", i, "k", "above 256", b.k, true);
  }
  for (uint32_t e = 0; e < model.edges.size(); ++e) {
    if (model.edges[e].rest < 0) return bad("skin edge", e, "rest", "negative rest length", model.edges[e].rest, true);
    if (model.edges[e].k > kMaxStiffness) return bad("skin edge", e, "k", "above 256", model.edges[e].k, true);
  }
  for (uint32_t v = 0; v < n; ++v) {
    if (model.anchor_stiffness[v] > kMaxStiffness)
      return bad("skin anchor", v, "stiffness", "above 256", model.anchor_stiffness[v], true);
    if (model.fat[v] < 0) return bad("skin fat", v, "thickness", "negative", model.fat[v], true);
  }
  const LayerStatus params = check_params(model.params);
  if (!params.ok()) return params;
  const LayerStatus solver = check_solver(model.solver);
  return solver.ok() ? check_surface(model.surface, dynamic) : solver;
}

LayerStatus skin_validate(const SkinModel& model, const rig::Rig& rig, const muscle::MuscleModel& muscles) {
  if (model.joint_count != rig.joint_count())
    return bad("skin model", -1, "joint_count", "differs from the rig's joint count", model.joint_count, true);
  return skin_check_indices(model, muscles, rig.joint_count());
}

}  // namespace sinew::elastic_skin
