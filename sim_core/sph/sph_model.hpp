// The SPH elastic-joint model (sph-elastic-joints-tresca): particles filling
// the soft tissue around one joint, each bound to the rest frame of the bone
// on its side of the joint, and the per-substep gains of the particle
// dynamics. Produced offline (host_tools/layers/sph); read-only at run time.
// docs/sph.md derives every gain from its physical parameter.
#pragma once

#include <cstddef>
#include <cstdint>
#include <span>

#include "sim_core/fixed/vec3.hpp"
#include "sim_core/layer/layer_status.hpp"
#include "sim_core/rig/rig.hpp"

namespace sinew::sph {

// Documented maxima. They bound the worst-case work of one step.
inline constexpr uint32_t kMaxParticles = 8192;  // particle indices fit in uint16
inline constexpr uint32_t kMaxNeighbours = 96;   // per particle, per substep
inline constexpr uint32_t kMaxSubsteps = 16;

// The substep rule, the one place it is written: the substeps of the SPH
// integration at a tick rate (rate_hz > 0) keep dt <= 5 ms (k_e dt^2 <= 0.075
// with the default gains), and are at least 2 (docs/sph.md). rigc builds a
// joint's gains with it and the pipeline converts them with it for another
// loop rate; a rate below 13 Hz needs more than kMaxSubsteps (refused).
constexpr uint32_t substeps_for_rate(uint32_t rate_hz) {
  const uint32_t s = (200 + rate_hz - 1) / rate_hz;
  return s < 2 ? 2 : s;
}
inline constexpr uint32_t kMaxGridDim = 64;  // cells per axis of the neighbour grid
inline constexpr uint32_t kMaxSkinVertices = 1u << 16;
inline constexpr uint32_t kMaxVertexNeighbours = 64;  // particles interpolated per skin vertex

enum class Bone : uint8_t { kProximal = 0, kDistal = 1 };

// Q formats used below:
//   Len   Q12.20 rig units (as the rig; one rig unit = 2^length_exponent m)
//   Unit  Q2.30
//   Dens  Q8.24 normalised density: sum over neighbours of (1 - q^2)^3, q =
//         distance / h (Mueller 2003 poly6 without its constant, which the
//         equal particle masses and the pressure gain absorb). A particle
//         alone has density 1.0; the bulk of a lattice at h = 2 spacings ~11.
using Dens = int32_t;
inline constexpr int kDensFracBits = 24;
inline constexpr Dens kDensOne = int32_t{1} << kDensFracBits;

struct SphParams {
  fx::Len h = 0;                // kernel radius, rig units, > 0
  uint32_t substeps = 0;        // per tick, 1..kMaxSubsteps
  uint32_t max_neighbours = 0;  // per particle, 1..kMaxNeighbours
  // Velocities are kept in Len per substep, so every gain below is a
  // dimensionless acceleration x dt^2 (dt = tick / substeps), Q2.30.
  fx::Unit elastic_gain = 0;    // k_e dt^2: pull toward the skinned rest position, [0, 1)
  fx::Unit pressure_gain = 0;   // k_p dt^2 / h: equation of state p = k_p (rho - rho0), [0, 1)
  fx::Unit viscosity_gain = 0;  // mu dt: viscosity Laplacian, [0, 1)
  fx::Unit damping = 0;         // velocity kept per substep, 1 - c dt, (0, 1]; damping x v truncated toward 0
  // External load: rig units per substep^2 per newton, dt^2 / (m unit),
  // with m the mass of one particle; Q2.30, >= 0.
  fx::Unit load_gain = 0;
  Dens tau_f = 0;            // Tresca limit (rho_max - rho_min) / 2, eq. (4); > 0
  uint32_t yield_count = 0;  // yielded particles that make the joint yield, >= 1
  fx::Len grid_radius = 0;   // half side of the neighbour grid centred on the joint
  // Colour-field surface tension (Mueller 2003 §4.4; docs/sph.md), in rig
  // units per substep^2 per unit of the normalised curvature term, Q2.30:
  // 6 sigma h dt^2 / (m C unit), C = 315 / (64 pi) the poly6 constant, m the
  // mass of one particle. 0 = off; [0, 1).
  fx::Unit tension_gain = 0;
};

// Surface particles only: |sum_j (1 - q^2)^2 d_ij / rho_j| (the colour
// gradient |h grad c_s| / 6) at least this, Q2.30 (1/8). On a cubic lattice
// at h = 2 spacings it is 0.06..0.08 in the interior (the neighbours'
// densities differ near the surface) and 0.19..0.26 on faces, edges and
// corners: below the threshold the normal is not a surface's. Mueller 2003
// §4.4 uses the same kind of threshold on |n|.
inline constexpr int32_t kTensionNormalMin = int32_t{1} << 27;

// The driven joint: the distal bone flexes about `axis` through the origin of
// the distal joint's frame; its flexion comes out of the particles.
struct SphJoint {
  uint32_t proximal_joint = 0;   // rig joint whose model transform carries kProximal particles
  uint32_t distal_joint = 0;     // rig joint whose model transform carries kDistal particles
  fx::Vec3 axis{0, 0, 0};        // flexion axis, unit (Q2.30), in the distal joint's frame
  fx::Vec3 load_point{0, 0, 0};  // where the external force acts, Len, distal joint's frame
};

struct SphModel {
  SphParams params;
  SphJoint joint;
  std::span<const fx::Len> rest_local[3];  // particle rest position in its bone's frame, SoA
  std::span<const fx::Len> rest_model[3];  // the same in model space at the rig's rest pose
  std::span<const uint8_t> bone;           // Bone per particle
  std::span<const uint32_t> skin_vertex;   // rig vertices within h of a particle at rest
  std::span<const fx::Len> skin_rest[3];   // their rest positions, model space, SoA

  uint32_t particle_count() const { return static_cast<uint32_t>(bone.size()); }
  uint32_t skin_count() const { return static_cast<uint32_t>(skin_vertex.size()); }
};

// The layer status (sim_core/layer/layer_status.hpp); messages name the
// offending field.
using layer::LayerError;
using layer::LayerStatus;

// The layer's safety contract: every count, index and parameter against the
// ranges above, and the joints and skin vertices against the rig it runs on.
LayerStatus sph_validate(const SphModel& model, const rig::Rig& rig);

// The same checks without a rig (joint and vertex indices unchecked): what
// sph_state_bytes and sph_init can verify of a model on its own.
LayerStatus sph_validate_model(const SphModel& model);

}  // namespace sinew::sph
