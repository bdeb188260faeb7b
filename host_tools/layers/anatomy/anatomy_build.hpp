// The offline builder of the anatomy layers: AnatomySpec + a loaded rig ->
// the fixed-point muscle and skin models (owning their storage).
//   1. attachments: bone-size parameters -> Len points in the joint frames;
//   2. rest lengths: sim_core's own muscle step at the rest pose, so the
//      runtime scale is exactly 1 there;
//   3. anchoring (§5.1): every rig vertex to its nearest component - a
//      muscle segment (trilinear (s, t, u) by Newton-Raphson) or the bones
//      (the vertex's two strongest rig influences, blended);
//   1b. shapes (§4.2, Table 1): bone normals at the attachments, slice
//      edits as rotation columns, the pivot mode;
//   4. springs: k_e = (a1 + a2) / len^2 (eq. 1), k_a = C_a sum(a_i) / 3
//      (eq. 2), areas in units of the mean rest edge length squared.
// Doubles use + - * / and sqrt only (compiled with -ffp-contract=off), so
// the models are bit-identical on every platform.
#pragma once

#include <string>
#include <vector>

#include "anatomy_spec.hpp"
#include "sim_core/elastic_skin/skin_model.hpp"
#include "sim_core/muscle/muscle_model.hpp"
#include "sim_core/rig/rig.hpp"

namespace sinew::anatomy_build {

struct BuildReport {
  uint32_t muscle_anchors = 0, bone_anchors = 0, edges = 0, bands = 0;
  double max_newton_residual = 0;    // model units, worst trilinear inverse
  double max_rest_anchor_error = 0;  // model units: forward map at rest vs rest position
  double mean_edge_length = 0;       // model units
  // The dynamic skin's solver as built (derived or given), SI.
  double vertex_mass = 0, stiffness_scale = 0, anchor_damping = 0, omega_max = 0;
  uint32_t substep_hz = 0;
};

struct AnatomyModel {
  std::vector<muscle::MuscleRecord> muscles;
  std::vector<muscle::PrimitiveRecord> primitives;
  std::vector<muscle::PrimitiveDeformation> deformations;  // empty (none deformed) or one per primitive
  std::vector<muscle::MuscleShape> shapes;                 // empty (all default shapes) or one per muscle
  std::vector<muscle::PrimitiveExponents> exponents;       // empty (all exponents 2, 4 or 8) or one per primitive
  std::vector<elastic_skin::Anchor> anchors;
  std::vector<elastic_skin::Stiffness> anchor_stiffness;
  std::vector<fx::Len> fat;
  std::vector<elastic_skin::Edge> edges;
  std::vector<elastic_skin::RubberBand> bands;
  std::vector<uint32_t> triangles;  // the rig's faces, when the fat follows the mesh normal or the skin is inflated
  uint32_t joint_count = 0, ring_vertices = 8;
  elastic_skin::SkinParams params;
  elastic_skin::SkinSolverParams solver;
  elastic_skin::SkinSurfaceParams surface;
  BuildReport report;

  muscle::MuscleModel muscle_model() const {
    return {joint_count, ring_vertices, muscles, primitives, deformations, shapes, exponents};
  }
  elastic_skin::SkinModel skin_model() const {
    return {joint_count, static_cast<uint32_t>(anchors.size()),
            anchors,     anchor_stiffness,
            fat,         edges,
            bands,       params,
            solver,      triangles,
            surface};
  }
};

// Returns false with a message naming the muscle, primitive or vertex.
bool build_anatomy(const rig::Rig& rig, const AnatomySpec& spec, AnatomyModel* out, std::string* error);

}  // namespace sinew::anatomy_build
