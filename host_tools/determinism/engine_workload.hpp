// The engine reference workload: a built-in rig (compiled in-process, so the
// blob itself is part of what is checked) driven over a fixed trajectory of
// joint inputs; every step's positions and normals are hashed.
#pragma once

#include <cstdint>
#include <span>
#include <string>

namespace sinew::determinism {

struct EngineRun {
  uint64_t blob_hash = 0;    // xxHash64 of the compiled rig blob
  uint64_t output_hash = 0;  // xxHash64 of every step's outputs
  uint32_t vertices = 0;
  uint32_t clamped_dofs = 0;  // summed over the run
  double seconds = 0;         // wall time of the steps (informational)
};

// rig: "arm" or "hand". Returns false (with a message) if the rig fails to
// compile or load.
bool run_engine_workload(const std::string& rig, int steps, EngineRun* out, std::string* error);

// Deterministic trajectory: input i at step s, a signed binary angle sweeping
// smoothly through (and past) each DOF's range. The shared sweep
// (hal/sim/sweep.hpp) the daemon's trajectory source also plays.
int32_t trajectory_input(uint32_t input, uint32_t step);

inline constexpr int kEngineSteps = 200;

}  // namespace sinew::determinism
