// The anatomy layer's offline side (layers/common/layer_compile.hpp): its
// [[muscle]], [[rubber_band]] and [skin] tables and their compilation into
// the MUSC and SKIN sections.
#pragma once

#include <array>
#include <string>
#include <utility>
#include <vector>

#include "host_tools/layers/anatomy/anatomy_spec.hpp"
#include "host_tools/layers/common/layer_compile.hpp"

namespace sinew::layers {

struct MuscleTable {
  std::string name;
  JointRef origin, insertion;
  rigc::Vec3d side{0, 0, 0};  // model-space side of the belly; zero: the inner side of the bend
  double thickness = 1.0;
  std::string where;
  // Non-default shape (anatomically-based-modeling §4.2-4.3, Table 1) and
  // the belly primitive's Barr deformations (anatomy_spec.hpp ranges).
  bool end_axes_from_bones = true;  // end-slice Z from the bones' surface normals (§4.2)
  int pivot = 0;                    // 0 off, 1 on, 2 variable: a pivot over the insertion joint
  std::array<anatomy_build::SliceEditSpec, 8> slice_edit{};  // Table 1 translate / rotate per slice
  double belly_taper = 0, belly_twist = 0, belly_bend = 0;   // twist, bend in degrees
  double belly_exponent = 4, belly_exponent_z = 0;           // superquadric exponents; 0: exponent_z = exponent
  bool band = true;  // the default fascia band at the belly (LEMAN §5.5); [[rubber_band]] adds others
};

// LEMAN §5.5: a rubber band from a skin point to a muscle. The builder
// traces the skin point's inward normal to the muscle's surface and binds
// the band to the ring vertex nearest the hit (anatomy_spec.hpp).
struct RubberBandTable {
  std::string muscle;      // a [[muscle]] name
  int slice = 4;           // [0, 7]: the muscle point that picks the skin vertex when `vertex` is absent
  int ring_vertex = -1;    // [0, ring): -1 the belly's outermost (3/4 turn, as the default band)
  int vertex = -1;         // skin (rig) vertex; -1: the one nearest the muscle point (slice, ring_vertex) at rest
  double stiffness = 0.5;  // model stiffness (eq. (1)'s units, as the skin's springs), > 0
  std::string where;
};

struct SkinTable {
  bool on = false;
  std::string where;
  int iterations = 10;                   // relaxations per tick
  bool warm_start = true;                // start each tick from the last one's skin (LEMAN)
  std::string mode = "static";           // "static" (relaxation) | "dynamic" (LEMAN §3 mass-spring)
  anatomy_build::SkinSolverSpec solver;  // mode is written into solver.dynamic
  // External inputs measuring the acceleration of the rig's base (the frame
  // its bones are given in), x, y, z in the rig's axes, m/s^2; declared
  // (acceleration, +-200 m/s^2) if no [[external_input]] has the name. Empty:
  // no base motion (LEMAN §3: the dynamic skin feels -a_base).
  std::vector<std::string> base_acceleration;
  // LEMAN §5.6 per-point fat: (rig vertex, thickness in model units)
  // replacing the derived uniform thickness at that vertex ([skin] fat adds
  // to every vertex on top).
  std::vector<std::pair<int, double>> fat_vertices;
};

struct AnatomyTables {
  std::vector<MuscleTable> muscles;
  std::vector<RubberBandTable> rubber_bands;
  SkinTable skin;
  bool empty() const { return muscles.empty() && rubber_bands.empty() && !skin.on; }
};

template <>
struct HostLayer<pipeline::Stage::kAnatomy> {
  using Tables = AnatomyTables;
  static void bent_joints(const Tables&, std::vector<const JointRef*>*) {}
  // The skin's base-acceleration inputs.
  static bool declare_inputs(const rigc::RigSpec& spec, const Tables& tables, std::vector<ExternalInputTable>* external,
                             std::string* error);
  static bool compile(const LayerCompile& c, const Tables& tables, std::string* error);
};

}  // namespace sinew::layers
