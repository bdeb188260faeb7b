// Offline builder of the SPH elastic-joint model (sim_core/sph): fills a
// capsule of soft tissue around a chosen joint of a rig with a deterministic
// jittered lattice of particles, binds each to the bone on its side of the
// joint, converts the physical parameters into the per-substep fixed-point
// gains, and calibrates the Tresca limit tau_f the way the paper does (§5):
// the density spread of the tissue flexed to the yield angle.
//
// Double precision, but only + - * / and std::sqrt (compiled with
// -ffp-contract=off) and sim_core's integer trig: the model is bit-identical
// on every platform.
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <vector>

#include "host_tools/rigc/rig_spec.hpp"
#include "sim_core/fixed/mat34.hpp"
#include "sim_core/sph/sph_model.hpp"

namespace sinew::layers {

// The largest flexion a default calibration uses: the elastic pull's
// restoring torque k_e I sin(theta) peaks at 90 degrees, so beyond it no
// constant load has a static equilibrium and a limit placed there is never
// reached statically (docs/sph.md, "Tresca").
inline constexpr double kMaxCalibrationDeg = 90;

// The calibration flexion a build uses: the option if > 0, else the joint's
// maximum flexion capped at kMaxCalibrationDeg (90 if it has none above 0).
double calibration_angle_deg(const rigc::RigSpec& spec, int distal_joint, double yield_angle_deg);

struct SphBuildOptions {
  uint32_t particle_count = 1000;
  std::string proximal_joint = "shoulder";     // bone carrying the particles before the joint
  std::string distal_joint = "elbow";          // the driven joint (its first DOF axis is the flexion axis)
  int proximal_index = -1, distal_index = -1;  // >= 0: the joints by index (names are then ignored)
  double capsule_half_length = 0.08;           // metres along the bone on each side of the joint
  double capsule_radius = 0.036;               // metres (inside the arm's skin)
  double kernel_ratio = 2.0;                   // h / lattice spacing
  double jitter = 0.2;                         // lattice jitter, fraction of the spacing
  uint64_t seed = 0x5eedu;
  double tick_hz = 1000;
  uint32_t substeps = 2;
  uint32_t max_neighbours = 64;
  double tissue_mass = 1.0;          // kg, shared equally by the particles
  double elastic_stiffness = 3000;   // k_e, 1/s^2: pull toward the skinned rest position
  double pressure_stiffness = 2000;  // k_p, h/s^2 per unit of normalised density
  double viscosity = 20;             // mu, 1/s
  double damping = 40;               // c, 1/s
  double surface_tension = 0;        // sigma, N/m: colour-field tension (Mueller 2003 §4.4); 0 = off
  double load_distance = 0.25;       // metres from the joint along the distal bone (the wrist)
  // Flexion whose peak density spread defines tau_f (paper §5: the maximum
  // bendable angle). 0: the distal joint's maximum flexion (its first DOF's
  // upper limit), at most kMaxCalibrationDeg (docs/sph.md).
  double yield_angle_deg = 0;
  double yield_scale = 1.0;  // tau_f multiplier (1: the paper's calibration)
  uint32_t yield_count = 0;  // 0: 1 % of the particles (at least 1)
  // Overrides for tests of the validator (applied after calibration); < 0: keep.
  int64_t override_h = -1;
  int64_t override_tau_f = -1;
};

// Owns the arrays an sph::SphModel points at.
struct SphBuilt {
  std::array<std::vector<fx::Len>, 3> rest_local, rest_model, skin_rest;
  std::vector<uint8_t> bone;
  std::vector<uint32_t> skin_vertex;
  sph::SphParams params;
  sph::SphJoint joint;
  int32_t length_exponent = 0;
  double h_metres = 0, spacing_metres = 0;
  sph::SphModel model() const;  // views into this object
};

// Returns false with a message naming the option or joint at fault.
bool build_sph(const rigc::RigSpec& spec, const SphBuildOptions& options, SphBuilt* out, std::string* error);

// Model-space rest transforms of the spec's joints (quantised as the rig
// compiler does; rest rotations must be identity).
bool rest_transforms(const rigc::RigSpec& spec, int32_t length_exponent, std::vector<fx::Mat34>* out,
                     std::string* error);

}  // namespace sinew::layers
