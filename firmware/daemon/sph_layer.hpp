// The SPH elastic elbow (docs/sph.md, sph-elastic-joints-tresca) in the
// daemon: built once at start-up from the built-in arm's spec (the rig blob
// has no SPH section yet) for the loop's tick rate, then stepped every tick.
// It declares one external input, "<elbow>.force": the force (newtons,
// Q16.16) a sensor measures at the wrist, pushing the forearm toward flexion;
// the particles' bend is added to the commanded elbow angle, the arm is
// skinned again with it and the eq. (2) displacement is added near the joint.
// Once the joint has yielded (Tresca), the elbow's inputs carry
// hal::kJointYielded in every frame. A stale force input holds its last good
// value, as every input does. Below 100 Hz the layer takes more substeps per
// tick (dt <= 5 ms); below 12.5 Hz it refuses the rate.
#pragma once

#include <memory>
#include <string>

#include "firmware/runtime/runtime.hpp"
#include "loaded_rig.hpp"

namespace sinew::firmware {

struct SphLayerOptions {
  uint32_t particles = 500;
  uint32_t tick_hz = 1000;
  double force_max_n = 40;  // the force input's range: [-force_max_n, force_max_n]
};

// Adds the force input to `rig` (call before the input limits and the sources
// are made).
std::unique_ptr<PoseLayer> make_arm_sph_layer(LoadedRig* rig, const SphLayerOptions& options, std::string* error);

}  // namespace sinew::firmware
