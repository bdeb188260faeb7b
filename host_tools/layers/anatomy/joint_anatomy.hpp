// Muscles and an elastic skin for any rig, from the bones a spec names
// (anatomically-based-modeling §4.1: attachments in units of the bone's
// "bounding box", so one description fits bones of any size). Every bone's
// box comes from the rig's geometry (layers/common/rig_geometry.hpp): its
// length, and a bone radius of 0.27 x the skin radius (the arm's 1.2 cm in 4.5 cm) around it; a muscle's
// attachments, slice profile, belly primitive and rubber band are the
// built-in arm's biceps proportions scaled to those boxes.
#pragma once

#include <string>
#include <vector>

#include "anatomy_spec.hpp"
#include "host_tools/layers/common/rig_geometry.hpp"

namespace sinew::anatomy_build {

struct MuscleRequest {
  std::string name;
  int origin = -1, insertion = -1;  // joints: the origin must be the insertion or one of its ancestors
  Vec3d side{0, 0, 0};              // model-space side the belly lies on; zero: the inner side of the bend
  double thickness = 1.0;           // multiplies the derived slice radii
  // Non-default shape (anatomically-based-modeling §4.2-4.3, Table 1) and
  // the belly primitive's Barr deformations (anatomy_spec.hpp ranges).
  bool end_axes_from_bones = true;                          // end-slice Z from the bones' surface normals (§4.2)
  int pivot = 0;                                            // 0 off, 1 on, 2 variable: a pivot over the insertion joint
  std::array<SliceEditSpec, 8> slice_edit{};                // Table 1 translate / rotate per slice
  double belly_taper = 0, belly_twist = 0, belly_bend = 0;  // twist, bend in degrees
  // The belly's superquadric exponents (PrimitiveSpec): across, and along
  // the muscle (0: the same as across); [1, 16].
  double belly_exponent = 4, belly_exponent_z = 0;
  bool band = true;  // a fascia band at the belly's outermost point (LEMAN §5.5)
};

struct SkinRequest {
  int iterations = 10;
  bool warm_start = true;
  double anchor_coefficient = 0.1;
  SkinSolverSpec solver;  // static relaxation by default
  // Bands beyond the muscles' own (muscle: index into the requests;
  // ring_vertex -1: the belly's outermost, 3/4 turn) and per-vertex fat
  // thicknesses (model units) replacing the derived uniform one.
  std::vector<RubberBandSpec> bands;
  std::vector<std::pair<int, double>> fat_overrides;
};

// A muscle's rest path in the mesh's bind space (origin and insertion
// midpoints) and its widest slice: what the skin's support region is
// measured from.
struct MusclePath {
  Vec3d origin{0, 0, 0}, insertion{0, 0, 0};
  double half_width = 0;
};

// Fails, naming the muscle and the problem, when the bones cannot carry it.
bool joint_anatomy(const rigc::RigSpec& rig, const layers::RigGeometry& geometry,
                   const std::vector<MuscleRequest>& muscles, const SkinRequest& skin, AnatomySpec* out,
                   std::vector<MusclePath>* paths, std::string* error);

}  // namespace sinew::anatomy_build
