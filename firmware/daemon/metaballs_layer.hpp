// The metaballs layer (docs/metaballs.md) in the daemon: built once at start-up
// from the built-in arm's spec (the rig blob has no metaballs section yet),
// then applied after skinning every tick, rewriting the vertex positions.
// Normals keep the skinning's.
#pragma once

#include <memory>
#include <string>

#include "firmware/runtime/runtime.hpp"

namespace sinew::firmware {

std::unique_ptr<PoseLayer> make_arm_metaballs_layer(const rig::Rig& rig, std::string* error);

}  // namespace sinew::firmware
