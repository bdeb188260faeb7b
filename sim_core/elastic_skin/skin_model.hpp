// Elastic skin over bones and muscles (anatomically-based-modeling §5, LEMAN
// §3, §5.4-5.6): the immutable model a builder produces (host_tools/layers/
// anatomy) and the runtime reads. Plain records behind spans.
//
// Units: positions and lengths Len (Q12.20 rig units); directions Q2.30;
// trilinear parameters Q8.24; stiffnesses Q16.16 (dimensionless: areas are
// measured in units of the mesh's mean rest edge length squared).
#pragma once

#include <cstdint>
#include <span>

#include "sim_core/fixed/vec3.hpp"

namespace sinew::elastic_skin {

using Stiffness = uint32_t;  // Q16.16, [0, kMaxStiffness]
inline constexpr int kStiffnessFracBits = 16;
inline constexpr Stiffness kStiffnessOne = Stiffness{1} << kStiffnessFracBits;
inline constexpr Stiffness kMaxStiffness = Stiffness{1} << 24;  // 256.0: keeps every sum far from int64 limits
inline constexpr uint32_t kMaxIterations = 256;
inline constexpr uint32_t kMaxVertices = 1u << 20;
inline constexpr uint32_t kMaxNewtonSteps = 8;
// Trilinear anchor parameters must lie within these bounds (Q8.24), or the
// anchor is "outside every component": s, t in [-16, 16] (the cell is
// extrapolated sideways: skin lies outside the muscle), u in [-1, 2].
inline constexpr int32_t kMaxAnchorST = int32_t{16} << 24;
inline constexpr int32_t kMinAnchorU = -(int32_t{1} << 24);
inline constexpr int32_t kMaxAnchorU = int32_t{2} << 24;

enum class AnchorKind : uint8_t {
  kBone = 0,    // rigid on up to two bones, blended (generalised tissue around a joint)
  kMuscle = 1,  // parametric trilinear (s, t, u) in a muscle segment (§5.1, Figure 6)
};

// The virtual anchor of one skin vertex: its rest position relative to its
// underlying component, mapped forward every step (§5.1).
struct Anchor {
  uint8_t kind = 0;  // AnchorKind
  uint8_t reserved[3] = {};
  uint32_t component = 0;                       // kBone: first bone (joint); kMuscle: muscle index
  uint32_t bone_b = 0;                          // kBone: second bone (== component for one bone)
  uint32_t segment = 0;                         // kMuscle: the cell between slices segment and segment + 1 (0..6)
  fx::Unit weight_b = 0;                        // kBone: weight of bone_b, [0, 1] in Q2.30
  fx::Vec3 local_a{0, 0, 0}, local_b{0, 0, 0};  // kBone: rest position in each bone's frame (Len)
  fx::Lin param[3] = {};                        // kMuscle: (s, t, u), Q8.24
  // Rest outward skin normal, Q2.30: kBone in each bone's frame (normal_a,
  // normal_b); kMuscle in the slice frame (X, Y, Z) of `segment` (normal_a).
  fx::Vec3 normal_a{0, 0, 0}, normal_b{0, 0, 0};
};

// A skin edge spring: k_e = (a1 + a2) / len^2 (eq. 1), rest length already
// multiplied by the rest-length ratio (§5.2: "slightly stretched").
struct Edge {
  uint32_t a = 0, b = 0;
  fx::Len rest = 0;
  Stiffness k = 0;
};

// LEMAN §5.5 "rubber band": a zero-length spring from a skin vertex to a
// muscle ring vertex.
struct RubberBand {
  uint32_t vertex = 0;
  uint32_t muscle = 0, slice = 0, ring_vertex = 0;
  Stiffness k = 0;
};

struct SkinParams {
  uint32_t iterations = 30;  // relaxations per step (§5.2; ~30 reach equilibrium), 1..kMaxIterations
  // Compressed edges push back weaker (§5.2): the stiffness multiplier is 1
  // for length excess >= 0, push_back below -compression_band * rest, and
  // linear in between.
  fx::Unit push_back = fx::kUnitOne / 10;
  fx::Unit compression_band = fx::kUnitOne / 10;  // (0, 1]
  // Collision sphere under each anchor (§5.2): radius R, centre R below the
  // virtual anchor along its normal; 0 disables.
  fx::Len collision_radius = 0;
  // Reaction constraints (LEMAN §3): in every iteration but the last a point
  // inside a primitive removes this fraction of its penetration (first-order,
  // critically damped: no overshoot); the last iteration removes all of it.
  fx::Unit reaction_gain = fx::kUnitOne / 2;  // (0, 1]
  uint32_t newton_steps = 3;                  // per push-out, 1..kMaxNewtonSteps
  uint8_t warm_start = 0;    // 1: start from the last step's skin (LEMAN); 0: from the virtual anchors (§5.1)
  uint8_t reserved[3] = {};  // explicit, zeroed: the record's bytes go into rig blobs as they are
};

// LEMAN §5.6: the skin lies the fat's thickness above the fat point along
// the skin's normal. kSurface re-estimates that normal from the deformed
// skin mesh (SkinModel::triangles) before every reaction pass: the
// area-weighted sum of the incident faces' normals, turned to the anchor
// normal's side (so the winding does not matter), the anchor normal where
// the sum vanishes (no incident face, degenerate faces).
enum class FatNormal : uint8_t {
  kAnchor = 0,   // the component-carried anchor normal (anatomically-based-modeling §5.1)
  kSurface = 1,  // the current skin mesh's normal (LEMAN §5.6)
};

enum class SkinMode : uint8_t {
  kStatic = 0,   // quasi-static relaxation every step (§5.2): no state but the warm start
  kDynamic = 1,  // LEMAN §3 mass-spring surface: per-vertex mass and velocity, integrated in time
};

// Q16.16 physical quantities of the dynamic mode (kg, N per rig unit, ...).
using Q16 = int32_t;
inline constexpr int kQ16FracBits = 16;
inline constexpr int kMassFracBits = 24;  // vertex mass, Q8.24 kg
// Accelerations (gravity, base), Q24.8 rig units / s^2: range for small rig
// units (9.81 m/s^2 is 2511 units/s^2 at 2^-8 m per unit, beyond Q12.20).
inline constexpr int kAccelFracBits = 8;
inline constexpr uint32_t kMaxSubsteps = 64;
inline constexpr uint32_t kMaxTickHz = 100000;
inline constexpr uint32_t kMaxSubstepHz = 1u << 20;
inline constexpr uint32_t kMaxConstraintPasses = 4;

// The solver switch and its parameters (both modes). Physical units: one
// rig unit of length is the unit below (with length_exponent 0 it is a
// metre, and every quantity is SI); time in seconds, mass in kg.
//
// Dynamic mode (LEMAN §3): m dv/dt = sum of spring forces + dashpots + m g
// - m a_base, integrated by semi-implicit (symplectic) Euler with the
// dashpots taken implicitly:
//   v' = v + (a_springs + a_ext + sum c_i/m (v_i - v)) / (H + sum c_i/m)
//   x' = x + v' / H,  H = tick_hz * n  (substep rate, 1/s)
// n = ceil(substep_hz / tick_hz) fixed substeps per tick (<= max_substeps),
// so the substep h = 1/H does not depend on the tick rate whenever
// substep_hz is a multiple of it. Anchors and rubber-band targets move
// linearly across a tick's substeps. Springs are explicit: stable for
// h * omega < 2; a step is refused unless h * omega_max <= 1 (margin 2),
// omega_max^2 <= max over vertices of (k_a + 2 sum k_e + sum k_r) / m
// (Gershgorin). Implicit dashpots are unconditionally stable.
struct SkinSolverParams {
  uint8_t mode = 0;  // SkinMode
  // FatNormal (both modes): the direction the fat layer offsets the skin
  // from its fat point. 0 (the default, and every layer before version 4):
  // the component-carried anchor normal, bit for bit as before.
  uint8_t fat_normal = 0;
  uint8_t reserved[2] = {};
  // Static mode (§5.2): stop after the first iteration whose largest move is
  // below this (Len); 0 runs every iteration. The last iteration run removes
  // all penetration either way.
  fx::Len tolerance = 0;
  // Dynamic: target substep rate (Hz), 1..kMaxSubstepHz. The default, 1 kHz,
  // is a multiple of the usual loop rates (1000, 500, 250, 200, 100 Hz), so
  // they all integrate with h = 1 ms; a skin whose h * omega_max exceeds 1
  // at that rate is refused at its first step and needs a higher one.
  uint32_t substep_hz = 1000;
  uint32_t max_substeps = 16;      // dynamic: bound on n, 1..kMaxSubsteps
  uint32_t constraint_passes = 3;  // dynamic: Gauss-Seidel reaction passes per substep (§6.11), 1..4
  int32_t vertex_mass = 167772;    // kg per skin vertex, Q8.24 (0.01 kg), > 0
  Q16 stiffness_scale = 50 << 16;  // N per rig unit for a model stiffness of 1.0 (k = k_model * scale), >= 0
  Q16 anchor_damping = 1 << 15;    // N s per rig unit, dashpot beside each anchor spring, >= 0
  Q16 band_damping = 1 << 15;      // N s per rig unit, dashpot beside each rubber band, >= 0
  // Fat thickness added to every vertex's own (§5.6: global + per point),
  // both modes, Len >= 0.
  fx::Len fat_thickness = 0;
  fx::Vec3 gravity{0, 0, 0};  // rig units / s^2, Q24.8 (kAccelFracBits; e.g. y up, metres: {0, -2511, 0})
  // Dynamic: N s per rig unit, a dashpot along each skin edge beside its
  // spring (LEMAN §3: the surface's springs with damping), >= 0; 0 (the
  // default) leaves the edges undamped, bit for bit as before. Explicit,
  // on the relative velocity along the edge: c ((v_b - v_a) . e) e on a.
  // A step is also refused unless h * gamma_max <= 1, gamma_max = max over
  // vertices of 2 c degree / m (with h * omega_max <= 1 this keeps every
  // damped mode of symplectic Euler stable).
  Q16 edge_damping = 0;
};

// How the dynamic mode advances the skin in time.
enum class SkinIntegrator : uint8_t {
  // Explicit symplectic Euler in fixed substeps (SkinSolverParams), the
  // reactions as position projections: the integrator before LEMAN's, kept
  // as an option (every rig built before SKIN version 6 runs it).
  kExplicit = 0,
  // LEMAN §6.11: one implicit (backward Euler) step per tick, its equation
  // of motion solved by `relaxation_iterations` Gauss-Seidel sweeps over the
  // vertices; the §3 surface (stretch: the edge springs; bend: the umbrella
  // term below), Platt-Barr reaction constraints and air pressure
  // (surface_relaxation.hpp).
  kRelaxation = 1,
};
inline constexpr uint32_t kMaxRelaxationIterations = 8;
inline constexpr int32_t kMaxReactionFrequency = 10000 << 16;  // Hz, Q16.16

// LEMAN's elastic surface (§3, §5.3, §6.11) in dynamic mode; read only with
// integrator = kRelaxation. Units as SkinSolverParams (rig units, s, kg).
struct SkinSurfaceParams {
  uint8_t integrator = 0;             // SkinIntegrator
  uint8_t relaxation_iterations = 3;  // Gauss-Seidel sweeps per step (§6.11: "typically two to four"), 1..8
  uint8_t reserved[2] = {};
  // Bend (Terzopoulos' second-order term of the §3 surface): the energy
  // 1/2 k_b sum_i |L(x - a)_i|^2, L the umbrella operator (mean of the edge
  // neighbours minus the vertex), a the virtual anchors: the skin keeps the
  // curvature its anchors carry. k_b = bend * stiffness_scale, Q16.16 model
  // stiffness [0, kMaxStiffness].
  Stiffness bend = 0;
  // §5.3 uniform internal air pressure, kg / (rig unit s^2) (N/m^2 with
  // metres), Q16.16, signed (negative: suction); the force on a vertex is
  // pressure times a third of its faces' area, along their outward normal.
  // Needs SkinModel::triangles.
  int32_t pressure = 0;
  // Platt-Barr reaction constraint (§3): a fat point inside a primitive
  // returns to its surface with critically damped motion of this natural
  // frequency (Hz, Q16.16, (0, kMaxReactionFrequency]); the force along the
  // surface normal is replaced, the tangential force left alone.
  int32_t reaction_frequency = 100 << 16;
};

struct SkinModel {
  uint32_t joint_count = 0;  // joints of the rig the model was built for
  uint32_t vertex_count = 0;
  std::span<const Anchor> anchors;              // one per vertex
  std::span<const Stiffness> anchor_stiffness;  // k_a = C_a * sum(a_i) / 3 (eq. 2), one per vertex
  std::span<const fx::Len> fat;                 // fat thickness below the skin (LEMAN §5.6), >= 0, one per vertex
  std::span<const Edge> edges;
  std::span<const RubberBand> bands;
  SkinParams params;
  SkinSolverParams solver;
  // The skin mesh's faces, 3 vertex indices each (the rig's triangles: the
  // skin's vertices are the rig's). Read only with solver.fat_normal =
  // kSurface; empty then leaves every vertex on its anchor normal.
  std::span<const uint32_t> triangles{};
  SkinSurfaceParams surface{};  // dynamic mode's integrator and LEMAN's surface terms
  // The support region the anatomy stage reads the skin at (ascending
  // vertex indices, the skin section's region_vertex; empty: every vertex).
  // The static relaxation moves the region and the vertices within
  // kHaloRings edges of it; the others stay on their anchors, where the
  // stage does not read them (docs/anatomy.md, "The moving vertices").
  std::span<const uint32_t> region{};
};

// Edge rings about the support region that the static relaxation moves
// with it: the region's border vertices keep springs to vertices that
// relax, and those to vertices on their anchors.
inline constexpr uint32_t kHaloRings = 8;

}  // namespace sinew::elastic_skin
