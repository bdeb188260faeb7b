// The physical layers a rig spec asks for ([[sph]], [metaballs], [[muscle]],
// [skin], [[barnet]], [[external_input]]; docs/rig-format.md lists every
// key), built for any skeleton by the offline builders and written into the
// rig blob as layer sections. A table holding only its required keys works
// on any model: every other parameter derives from the rig's geometry
// (layers/common/rig_geometry.hpp). Runs on the host only; the board loads
// the fixed-point results.
#pragma once

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "host_tools/layers/anatomy/anatomy_spec.hpp"
#include "host_tools/layers/metaballs/options.hpp"
#include "host_tools/rigc/rig_spec.hpp"

namespace sinew::layers {

// A joint named in a spec: by name, or by glTF node index where the model's
// nodes have no names. `where` ("file:line: key") prefixes every message.
struct JointRef {
  std::string name;
  int node = -1;  // >= 0: by glTF node index
  std::string where;
};

struct SphTable {
  JointRef joint;  // the joint whose bend the tissue carries; its parent's bone is the other side
  uint32_t particles = 500;
  double radius = 0;       // capsule radius; 0: 0.8 x the skin radius around the joint
  double half_length = 0;  // capsule half length; 0: min(2.2 x radius, 0.4 x the shorter bone)
  double tissue_mass = 0;  // kg; 0: 1000 kg/m^3 x the capsule volume (model units read as metres)
  double yield_angle_deg = 60;
  std::string force_input;     // external input of the force at the distal bone's end; "" -> "<joint>.force"
  double surface_tension = 0;  // sigma, N/m (0: off; docs/sph.md)
};

struct MetaballsTable {
  bool on = false;
  std::string where;
  double ball_spacing = 0;  // 0: 0.22 x the mean skin radius (at most 3000 balls along the bones)
  // Every other [metaballs] key (docs/metaballs.md); ball_spacing above and
  // the rig's rate_hz override theirs.
  metaballs_build::Options options;
};

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

struct BarnetTable {
  JointRef joint;
  int segments = 8, rings = 7;
  double ring_step = 0;  // 0: 0.65 x the skin radius
  double force = 0;      // 0: 1.1 x the skin radius (q x model units)
  // External inputs, declared (N, force, +-40; scalar, [1/256, 256]) if no
  // [[external_input]] has the name. force_input: activation 0 at 0, 1 at
  // force_input_full (its unit) instead of the flexion; q_input: scales every
  // bar's force density by its value.
  std::string force_input = {};
  std::string q_input = {};
  double force_input_full = 40;
  // barnet-driven-skinning's nets, on any rig: "joint", a ring net around
  // `joint` (Figure 2); "muscles", the flexor/extensor net along the bone
  // before `joint` (Figure 3; `segments` even, `force` apply); "wrinkles", a
  // wrinkle net on the skin mesh on the fold side of `joint` (Figure 6;
  // `force` applies). On the built-in arm only, the arm's own "arm-muscles"
  // and "arm-wrinkles" (the elbow's; the ring keys are ignored). Every net
  // takes force_input and q_input.
  std::string net = "joint";
};

struct ExternalInputTable {
  std::string name, unit = "N", quantity = "force";
  double min = -40, max = 40;
  std::string where;
};

struct LayerSpecs {
  uint32_t rate_hz = 1000;  // tick rate the rate-dependent layers (SPH) are built for
  std::vector<SphTable> sph;
  MetaballsTable metaballs;
  std::vector<MuscleTable> muscles;
  std::vector<RubberBandTable> rubber_bands;
  SkinTable skin;
  std::vector<BarnetTable> barnets;
  std::vector<ExternalInputTable> external;
  bool empty() const {
    return sph.empty() && !metaballs.on && muscles.empty() && rubber_bands.empty() && !skin.on && barnets.empty() &&
           external.empty();
  }
};

// Gives every joint a layer drives through an angle ([[sph]], [[barnet]])
// and that has no rotational DOF (glTF joints have none) one rotational DOF
// about its bend axis: the normal of the plane of its parent's bone and its
// own, or a perpendicular of the parent's bone where they are collinear;
// limits +-150 degrees. Run before compile_rig; one report line per joint.
bool add_layer_dofs(rigc::RigSpec* spec, const LayerSpecs& layers, std::vector<std::string>* report,
                    std::string* error);

// Appends the layer sections to `blob` (compile_rig's output for `spec`).
// `report` gets one line per layer. Errors name the spec line and the problem.
bool compile_layers(const rigc::RigSpec& spec, const LayerSpecs& layers, std::vector<uint8_t>* blob,
                    std::vector<std::string>* report, std::string* error);

// The joint index a reference names, or -1 with a message.
int resolve_joint(const rigc::RigSpec& spec, const JointRef& ref, std::string* error);

}  // namespace sinew::layers
